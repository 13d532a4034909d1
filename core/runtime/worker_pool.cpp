// SPDX-License-Identifier: MIT
#include "core/runtime/worker_pool.h"

#include <algorithm>

namespace ihf {

int WorkerPool::resolve(int threads)
{
	if (threads <= 0)
		threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
	return std::clamp(threads, 1, kMaxThreads);
}

WorkerPool::WorkerPool(int threads)
{
	threads = resolve(threads);
	workers_.reserve(static_cast<size_t>(threads - 1));
	for (int t = 1; t < threads; ++t)
		workers_.emplace_back([this, t] { workerLoop(t); });
}

WorkerPool::~WorkerPool()
{
	{
		std::lock_guard<std::mutex> lock(mutex_);
		stop_.store(true);
	}
	start_.notify_all();
	for (std::thread &w : workers_)
		w.join();
}

namespace {

// Spins of a waiting thread before it sleeps: some tens of microseconds.
constexpr int kSpins = 4000;

inline void relax()
{
#if defined(__x86_64__) || defined(__i386__)
	__builtin_ia32_pause();
#elif defined(__aarch64__) || (defined(__arm__) && __ARM_ARCH >= 7)
	asm volatile("yield");
#endif
}

// One step of a spin: a pause, and every 64th a yield of the core, so that a
// spinning thread gives way to a runnable one on a shared core.
inline void spinStep(int i)
{
	if ((i & 63) == 63)
		std::this_thread::yield();
	else
		relax();
}

} // namespace

// Claims tasks of run `generation` until none is left; the claim word
// balances uneven tasks. A worker that wakes after its run has moved on
// finds another generation in the word and claims nothing; the task count
// is in the same word, so a count is never taken from another run.
void WorkerPool::drain(int thread, uint32_t generation)
{
	uint64_t c = claim_.load(std::memory_order_acquire);
	for (;;) {
		if (static_cast<uint32_t>(c >> 32) != generation)
			return;
		const uint32_t tasks = static_cast<uint32_t>(c >> 16) & 0xffffu;
		const uint32_t i = static_cast<uint32_t>(c) & 0xffffu;
		if (i >= tasks)
			return;
		if (!claim_.compare_exchange_weak(c, c + 1, std::memory_order_acq_rel, std::memory_order_acquire))
			continue;
		task_(static_cast<int>(i) + offset_, thread);
		if (finished_.fetch_add(1, std::memory_order_acq_rel) + 1 == static_cast<int>(tasks)) {
			// The lock orders this with the caller's check before it sleeps.
			std::lock_guard<std::mutex> lock(mutex_);
			if (callerAsleep_)
				done_.notify_one();
		}
		c = claim_.load(std::memory_order_acquire);
	}
}

void WorkerPool::workerLoop(int thread)
{
	uint64_t seen = 0;
	for (;;) {
		uint64_t g = generation_.load(std::memory_order_acquire);
		for (int i = 0; i < kSpins && g == seen && !stop_.load(std::memory_order_relaxed); ++i) {
			spinStep(i);
			g = generation_.load(std::memory_order_acquire);
		}
		if (g == seen) {
			std::unique_lock<std::mutex> lock(mutex_);
			++sleepers_;
			start_.wait(lock, [&] { return stop_.load() || generation_.load() != seen; });
			--sleepers_;
			g = generation_.load();
		}
		if (stop_.load())
			return;
		seen = g;
		drain(thread, static_cast<uint32_t>(g));
	}
}

void WorkerPool::run(int tasks, FunctionRef<void(int, int)> task)
{
	if (tasks <= 0)
		return;
	if (workers_.empty() || tasks == 1) {
		for (int i = 0; i < tasks; ++i)
			task(i, 0);
		return;
	}
	for (int first = 0; first < tasks; first += kMaxTasksPerRun)
		runPart(first, std::min(tasks - first, kMaxTasksPerRun), task);
}

void WorkerPool::runPart(int first, int tasks, FunctionRef<void(int, int)> task)
{
	// Published by the release of the new claim word: every task of the
	// previous run has finished, so no worker reads these now.
	task_ = task;
	offset_ = first;
	finished_.store(0, std::memory_order_relaxed);
	uint32_t generation;
	bool wake;
	{
		// Under the mutex: a worker between its check and its sleep sees it.
		// The word first, so a worker that sees the generation sees its run.
		std::lock_guard<std::mutex> lock(mutex_);
		generation = static_cast<uint32_t>(generation_.load(std::memory_order_relaxed) + 1);
		claim_.store(uint64_t{generation} << 32 | static_cast<uint64_t>(tasks) << 16, std::memory_order_release);
		generation_.fetch_add(1, std::memory_order_release);
		wake = sleepers_ > 0;
	}
	if (wake)
		start_.notify_all();
	drain(0, generation);
	// Only tasks a worker claimed can still be running.
	for (int i = 0; i < kSpins && finished_.load(std::memory_order_acquire) != tasks; ++i)
		spinStep(i);
	if (finished_.load(std::memory_order_acquire) != tasks) {
		std::unique_lock<std::mutex> lock(mutex_);
		callerAsleep_ = true;
		done_.wait(lock, [&] { return finished_.load(std::memory_order_acquire) == tasks; });
		callerAsleep_ = false;
	}
}

} // namespace ihf
