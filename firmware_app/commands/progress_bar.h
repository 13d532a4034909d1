// SPDX-License-Identifier: MIT
#pragma once

// A progress line on stderr: redrawn in place on a terminal, a line every
// 10% otherwise (logs and CI).

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include <unistd.h>

namespace ihf::app {

class ProgressBar
{
public:
	explicit ProgressBar(std::string label)
		: label_(std::move(label)), tty_(isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()) {}

	void update(size_t done, size_t total)
	{
		std::lock_guard lock(mutex_);
		if (total == 0)
			return;
		int pct = static_cast<int>(100 * done / total);
		double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
		if (tty_) {
			int filled = pct * 30 / 100;
			std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %zu/%zu %.0fs", label_.c_str(), filled,
				     "==============================", 30 - filled, "", pct, done, total, s);
			if (done == total)
				std::fputc('\n', stderr);
		} else if (pct / 10 != lastDecile_ || done == total) {
			lastDecile_ = pct / 10;
			std::fprintf(stderr, "%s %3d%% %zu/%zu %.0fs\n", label_.c_str(), pct, done, total, s);
		}
	}

private:
	std::string label_;
	bool tty_;
	std::chrono::steady_clock::time_point start_;
	std::mutex mutex_;
	int lastDecile_ = -1;
};

} // namespace ihf::app
