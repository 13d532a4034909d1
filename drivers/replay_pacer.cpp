// SPDX-License-Identifier: MIT
#include "drivers/replay_pacer.h"

#include <cmath>

namespace ihf {

int64_t ReplayPacer::due(int64_t stampNs)
{
	if (!anchored_) {
		anchored_ = true;
		anchorClockNs_ = clock_->nowNs();
		anchorStampNs_ = stampNs;
	}
	return anchorClockNs_ + static_cast<int64_t>(std::llround(static_cast<double>(stampNs - anchorStampNs_) / speed_));
}

bool ReplayPacer::waitFor(int64_t stampNs, std::chrono::nanoseconds timeout)
{
	const int64_t at = due(stampNs);
	const int64_t now = clock_->nowNs();
	if (at > now + timeout.count()) {
		clock_->sleepUntil(now + timeout.count());
		return false;
	}
	clock_->sleepUntil(at);
	return true;
}

} // namespace ihf
