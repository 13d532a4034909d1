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

} // namespace

// Claims tasks until none is left; the atomic counter balances uneven tasks.
void WorkerPool::drain(int thread)
{
	for (int i = next_.fetch_add(1, std::memory_order_relaxed); i < tasks_;
	     i = next_.fetch_add(1, std::memory_order_relaxed))
		task_(i, thread);
}

void WorkerPool::workerLoop(int thread)
{
	uint64_t seen = 0;
	for (;;) {
		uint64_t g = generation_.load(std::memory_order_acquire);
		for (int i = 0; i < kSpins && g == seen && !stop_.load(std::memory_order_relaxed); ++i) {
			relax();
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
		drain(thread);
		if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
			// The lock orders this with the caller's check before it sleeps.
			std::lock_guard<std::mutex> lock(mutex_);
			done_.notify_one();
		}
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
	// Published by the release of the new generation.
	task_ = task;
	tasks_ = tasks;
	next_.store(0, std::memory_order_relaxed);
	busy_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
	bool wake;
	{
		// Under the mutex: a worker between its check and its sleep sees it.
		std::lock_guard<std::mutex> lock(mutex_);
		generation_.fetch_add(1, std::memory_order_release);
		wake = sleepers_ > 0;
	}
	if (wake)
		start_.notify_all();
	drain(0);
	for (int i = 0; i < kSpins && busy_.load(std::memory_order_acquire) != 0; ++i)
		relax();
	if (busy_.load(std::memory_order_acquire) != 0) {
		std::unique_lock<std::mutex> lock(mutex_);
		done_.wait(lock, [&] { return busy_.load(std::memory_order_acquire) == 0; });
	}
}

} // namespace ihf
