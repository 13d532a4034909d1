// SPDX-License-Identifier: MIT
#pragma once

// A fixed set of threads, started once, that run the independent tasks of one
// stage (the view search's rotations, ...) beside the calling thread. Nothing
// is allocated per run; a task gets its index and the index of the thread
// running it (0 = the caller), so per-thread scratch can be chosen without
// locks. Which thread runs which task varies from run to run: callers write
// results by task index and combine them in a fixed order, so the output is
// the same for any number of threads.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "core/common/function_ref.h"

namespace ihf {

class WorkerPool
{
public:
	static constexpr int kMaxThreads = 8;

	// threads: all threads a run uses, the caller included, in
	// [1, kMaxThreads]; 0 picks the machine's cores (at most kMaxThreads).
	explicit WorkerPool(int threads = 1);
	~WorkerPool();
	WorkerPool(const WorkerPool &) = delete;
	WorkerPool &operator=(const WorkerPool &) = delete;

	int threads() const { return static_cast<int>(workers_.size()) + 1; }
	// The threads a pool made with `threads` has.
	static int resolve(int threads);

	// Runs task(i, thread) for every i in [0, tasks) and returns when all
	// have finished. Not reentrant: a task must not call run().
	void run(int tasks, FunctionRef<void(int task, int thread)> task);

private:
	void workerLoop(int thread);
	// Tasks of one claim word (16 bits of it); longer runs go in parts.
	static constexpr int kMaxTasksPerRun = 0xffff;
	void runPart(int first, int tasks, FunctionRef<void(int, int)> task);
	void drain(int thread, uint32_t generation);

	std::vector<std::thread> workers_; // sized in the constructor only
	// A run's threads first spin briefly on the atomics, then sleep on the
	// condition variables: a stage dispatches many short runs (a wake-up
	// through the kernel alone costs ~25 us, measured), and a thread that
	// has to wait longer should not burn its core.
	std::mutex mutex_;
	std::condition_variable start_, done_;
	std::atomic<uint64_t> generation_{0}; // runs started
	// The current run's generation (bits 32-63), task count (16-31) and
	// next unclaimed task (0-15), in one word: a worker claims a task only of
	// the run it woke for, so one that wakes late (descheduled by another
	// process) claims nothing of a later run. A run ends when its tasks are
	// finished, not when every worker has checked in: the caller never waits
	// for a worker that is not running (BENCHMARKS.md, the pool under load).
	std::atomic<uint64_t> claim_{0};
	std::atomic<int> finished_{0}; // the current run's tasks finished
	std::atomic<bool> stop_{false};
	int sleepers_ = 0;       // workers waiting on start_ (under mutex_)
	bool callerAsleep_ = false; // the caller waits on done_ (under mutex_)
	FunctionRef<void(int, int)> task_;
	int offset_ = 0; // the current part's first task
};

} // namespace ihf
