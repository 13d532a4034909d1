// SPDX-License-Identifier: MIT
#pragma once

// A time budget per frame, shared by the frame's boxes. Each box, when it
// starts, gets an equal share of what is left (time a box does not use goes
// to the boxes after it). Work that can be cut (refinement iterations, the
// ICP polish) asks fits() with its predicted cost before it starts; work
// that cannot (the crop and the initial registration) just runs, and an
// exceeded deadline is counted as an overrun, never hidden.

#include <cstdint>

namespace ihf {

class FrameBudget
{
public:
	// budgetNs <= 0: unlimited (everything fits, nothing overruns).
	void beginFrame(int64_t nowNs, int64_t budgetNs, int boxes);
	void beginBox(int64_t nowNs);
	// Whether work predicted to take predictedNs, starting now, ends
	// before the current box's deadline.
	bool fits(int64_t nowNs, int64_t predictedNs) const;
	void endBox(int64_t nowNs);
	void endFrame(int64_t nowNs);

	bool unlimited() const { return budgetNs_ <= 0; }
	bool inFrame() const { return inFrame_; }
	int64_t boxDeadline() const { return boxDeadline_; }
	int64_t frameDeadline() const { return frameDeadline_; }

	uint64_t frames() const { return frames_; }
	uint64_t boxes() const { return boxes_; }
	uint64_t frameOverruns() const { return frameOverruns_; }
	uint64_t boxOverruns() const { return boxOverruns_; }
	int64_t worstFrameNs() const { return worstFrameNs_; }

private:
	bool inFrame_ = false;
	int64_t budgetNs_ = 0;
	int64_t frameStart_ = 0;
	int64_t frameDeadline_ = 0;
	int64_t boxDeadline_ = 0;
	int boxesLeft_ = 0;

	uint64_t frames_ = 0;
	uint64_t boxes_ = 0;
	uint64_t frameOverruns_ = 0;
	uint64_t boxOverruns_ = 0;
	int64_t worstFrameNs_ = 0;
};

} // namespace ihf
