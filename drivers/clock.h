// SPDX-License-Identifier: MIT
#pragma once

// Time as the frame sources see it: "now" and "sleep until". Real-time
// playback takes a PacingClock so tests can run it on simulated time.

#include <chrono>
#include <cstdint>
#include <thread>

namespace ihf {

class PacingClock
{
public:
	virtual ~PacingClock() = default;
	virtual int64_t nowNs() = 0;
	// Returns at or after deadlineNs (at once if it has passed).
	virtual void sleepUntil(int64_t deadlineNs) = 0;
};

// The host's monotonic clock.
class SteadyPacingClock : public PacingClock
{
public:
	int64_t nowNs() override
	{
		return std::chrono::duration_cast<std::chrono::nanoseconds>(
			       std::chrono::steady_clock::now().time_since_epoch())
			.count();
	}

	void sleepUntil(int64_t deadlineNs) override
	{
		std::this_thread::sleep_until(std::chrono::steady_clock::time_point(
			std::chrono::nanoseconds(deadlineNs)));
	}
};

} // namespace ihf
