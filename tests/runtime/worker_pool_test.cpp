// SPDX-License-Identifier: MIT
// WorkerPool: every task runs once per run, on a thread index in range, for
// any pool size and task count, over many short runs (the spinning hand-off
// between runs) and runs far apart (the sleeping one), and with more threads
// than cores, where a worker often wakes after its run has ended.

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "core/runtime/worker_pool.h"

namespace ihf {
namespace {

TEST(WorkerPool, ResolvesItsThreadCount)
{
	EXPECT_EQ(WorkerPool::resolve(1), 1);
	EXPECT_EQ(WorkerPool::resolve(3), 3);
	EXPECT_EQ(WorkerPool::resolve(100), WorkerPool::kMaxThreads);
	EXPECT_GE(WorkerPool::resolve(0), 1); // one per core
	EXPECT_LE(WorkerPool::resolve(0), WorkerPool::kMaxThreads);
	EXPECT_EQ(WorkerPool(3).threads(), 3);
	EXPECT_EQ(WorkerPool(1).threads(), 1);
}

TEST(WorkerPool, OneThreadRunsEveryTaskInOrderOnTheCaller)
{
	WorkerPool pool(1);
	std::vector<int> order;
	order.reserve(10);
	const std::thread::id caller = std::this_thread::get_id();
	bool onCaller = true;
	pool.run(10, [&](int task, int thread) {
		order.push_back(task);
		onCaller = onCaller && thread == 0 && std::this_thread::get_id() == caller;
	});
	ASSERT_EQ(order.size(), 10u);
	for (int i = 0; i < 10; ++i)
		EXPECT_EQ(order[static_cast<size_t>(i)], i);
	EXPECT_TRUE(onCaller);
	pool.run(0, [&](int, int) { FAIL() << "no task to run"; });
}

TEST(WorkerPool, EveryTaskRunsOnceOnAThreadInRange)
{
	for (int threads : {2, 3, 8}) {
		WorkerPool pool(threads);
		ASSERT_EQ(pool.threads(), threads);
		for (int tasks : {1, 2, 3, 7, 64, 1000, 70000}) {
			std::vector<std::atomic<int>> runs(static_cast<size_t>(tasks));
			std::atomic<int> badThread{0};
			pool.run(tasks, [&](int task, int thread) {
				runs[static_cast<size_t>(task)].fetch_add(1);
				badThread += thread < 0 || thread >= threads;
			});
			for (int i = 0; i < tasks; ++i)
				ASSERT_EQ(runs[static_cast<size_t>(i)].load(), 1) << threads << " threads, task " << i << " of " << tasks;
			EXPECT_EQ(badThread.load(), 0);
		}
	}
}

// Per-thread scratch indexed by the thread argument is never shared: two
// tasks on the same index never overlap in time.
TEST(WorkerPool, AThreadIndexIsNeverInTwoTasksAtOnce)
{
	WorkerPool pool(4);
	std::array<std::atomic<int>, WorkerPool::kMaxThreads> inside{};
	std::atomic<int> overlaps{0};
	for (int r = 0; r < 200; ++r)
		pool.run(16, [&](int, int thread) {
			if (inside[static_cast<size_t>(thread)].fetch_add(1) != 0)
				++overlaps;
			[[maybe_unused]] volatile int sink = 0; // a little work the optimiser keeps
			for (int spin = 0; spin < 200; ++spin)
				sink = spin;
			inside[static_cast<size_t>(thread)].fetch_sub(1);
		});
	EXPECT_EQ(overlaps.load(), 0);
}

TEST(WorkerPool, ManyShortRunsAndRunsAfterTheWorkersSlept)
{
	WorkerPool pool(2);
	long long sum = 0;
	for (int r = 0; r < 20000; ++r) {
		std::array<int, 2> part{};
		pool.run(2, [&](int task, int) { part[static_cast<size_t>(task)] = task + r; });
		sum += part[0] + part[1];
	}
	EXPECT_EQ(sum, 20000LL * 1 + 2LL * (20000LL * 19999 / 2));
	// Long enough apart that the workers stopped spinning and sleep.
	for (int r = 0; r < 3; ++r) {
		std::this_thread::sleep_for(std::chrono::milliseconds(20));
		std::atomic<int> ran{0};
		pool.run(5, [&](int, int) { ++ran; });
		EXPECT_EQ(ran.load(), 5);
	}
}

// A run ends when its tasks have finished, whether or not every worker has
// woken for it; a worker that wakes late must claim nothing, neither of the
// run it missed nor, with that run's task count, of the next. With twice as
// many threads as cores the workers are descheduled at any point, so late
// wake-ups happen all the time; task counts vary from run to run. (Reading
// the count apart from the claim, a version of the pool deadlocked here
// within milliseconds.)
TEST(WorkerPool, AWorkerThatWakesLateRunsNoTaskOfAnotherRun)
{
	const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
	WorkerPool pool(std::clamp(2 * cores, 4, WorkerPool::kMaxThreads));
	constexpr int kCounts[] = {2, 9, 3, 1, 17, 4};
	std::array<std::atomic<int>, 17> runs{};
	std::atomic<int> outside{0}, wrong{0};
	std::atomic<bool> live{false};
	for (int r = 0; r < 20000; ++r) {
		const int tasks = kCounts[r % 6];
		for (auto &n : runs)
			n.store(0);
		live.store(true);
		pool.run(tasks, [&](int task, int) {
			outside += !live.load();
			if (task < 0 || task >= tasks)
				++wrong;
			else
				runs[static_cast<size_t>(task)].fetch_add(1);
		});
		live.store(false);
		for (int i = 0; i < tasks; ++i)
			wrong += runs[static_cast<size_t>(i)].load() != 1;
	}
	EXPECT_EQ(outside.load(), 0);
	EXPECT_EQ(wrong.load(), 0);
}

} // namespace
} // namespace ihf
