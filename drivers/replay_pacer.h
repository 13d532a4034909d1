// SPDX-License-Identifier: MIT
#pragma once

// Real-time replay of a recording: the first frame after reset() anchors
// the recording's time to the clock's "now"; every later frame is due at
// that anchor plus its recorded time since the first one, divided by the
// speed. Shared by the file sources (which sleep until a frame is due) and
// ihf run's loop (which drops frames that are late).

#include <chrono>
#include <cmath>
#include <cstdint>

#include "drivers/clock.h"

namespace ihf {

class ReplayPacer
{
public:
	ReplayPacer(PacingClock &clock, double speed) : clock_(&clock), speed_(speed) {}

	// A speed due() can divide by: finite and > 0.
	static bool validSpeed(double speed) { return speed > 0 && std::isfinite(speed); }

	void reset() { anchored_ = false; }

	// The clock time at which the frame recorded at stampNs is due.
	int64_t due(int64_t stampNs);

	// Sleeps until that time and returns true; or, when it is further away
	// than timeout, sleeps the timeout and returns false (the frame stays
	// for the next call).
	bool waitFor(int64_t stampNs, std::chrono::nanoseconds timeout);

private:
	PacingClock *clock_;
	double speed_;
	bool anchored_ = false;
	int64_t anchorClockNs_ = 0;
	int64_t anchorStampNs_ = 0;
};

} // namespace ihf
