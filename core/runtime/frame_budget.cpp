// SPDX-License-Identifier: MIT
#include "core/runtime/frame_budget.h"

#include <algorithm>

namespace ihf {

void FrameBudget::beginFrame(int64_t nowNs, int64_t budgetNs, int boxes)
{
	inFrame_ = true;
	budgetNs_ = budgetNs;
	frameStart_ = nowNs;
	frameDeadline_ = nowNs + std::max<int64_t>(budgetNs, 0);
	boxDeadline_ = frameDeadline_;
	boxesLeft_ = std::max(boxes, 1);
}

void FrameBudget::beginBox(int64_t nowNs)
{
	if (unlimited()) {
		boxDeadline_ = nowNs;
		return;
	}
	const int64_t left = std::max<int64_t>(frameDeadline_ - nowNs, 0);
	boxDeadline_ = nowNs + left / std::max(boxesLeft_, 1);
	if (boxesLeft_ > 1)
		--boxesLeft_;
}

bool FrameBudget::fits(int64_t nowNs, int64_t predictedNs) const
{
	return unlimited() || nowNs + predictedNs <= boxDeadline_;
}

void FrameBudget::endBox(int64_t nowNs)
{
	++boxes_;
	if (!unlimited() && nowNs > boxDeadline_)
		++boxOverruns_;
}

void FrameBudget::endFrame(int64_t nowNs)
{
	if (!inFrame_)
		return;
	inFrame_ = false;
	++frames_;
	worstFrameNs_ = std::max(worstFrameNs_, nowNs - frameStart_);
	if (!unlimited() && nowNs > frameDeadline_)
		++frameOverruns_;
}

} // namespace ihf
