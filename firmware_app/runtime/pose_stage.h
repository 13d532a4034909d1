// SPDX-License-Identifier: MIT
#pragma once

// What `ihf run` does with a frame: take its boxes from the BoxFeed,
// convert the raw depth to millimetres (as `ihf estimate` converts a BOP
// depth PNG, so both give the same poses), hand the frame to the per-frame
// path (FrameEstimator: the cold estimator or the tracker, as
// `ihf estimate` does) and write a pose line per box, or an error line for
// a box whose object has no forest, a box without a pose, or a box line
// that did not parse; the other boxes go on. With tracking every line
// carries the box's mode and track. Buffers are sized in prepare().

#include <array>
#include <chrono>
#include <cstdio>
#include <string>

#include "drivers/clock.h"
#include "firmware_app/runtime/box_feed.h"
#include "firmware_app/runtime/frame_estimator.h"
#include "firmware_app/runtime/pose_output.h"
#include "firmware_app/runtime/run_loop.h"

namespace ihf::app {

struct PoseStageCounters {
	uint64_t frames = 0;
	uint64_t framesWithoutBoxes = 0;
	uint64_t boxes = 0;
	uint64_t poses = 0;
	uint64_t noPose = 0;
	uint64_t unknownObject = 0;
	uint64_t inputErrors = 0; // malformed box lines or boxes
	uint64_t deferred = 0; // boxes answered as waiting for a detection
};

class PoseStage : public FrameProcessor, private BoxSink
{
public:
	PoseStage(FrameEstimator &frames, BoxFeed &feed, PoseOutput &output, PacingClock &clock,
		  std::chrono::milliseconds boxesTimeout);

	Status prepare(const SourceInfo &info) override;
	Status process(const Frame &frame, int64_t arrivalNs) override;
	void describe(std::string &line) const override;
	bool interrupted() const override { return interrupted_; }

	const PoseStageCounters &counters() const { return counters_; }

private:
	Status onBox(const FrameBox &box, const ObjectModel *model, const StreamResult &result) override;

	FrameEstimator &frames_;
	BoxFeed &feed_;
	PoseOutput &output_;
	PacingClock &clock_;
	std::chrono::milliseconds boxesTimeout_;
	Status writeUnknownObject(uint64_t frame, int objId);
	Status writeResult(uint64_t frame, int objId, const PoseEstimate &e, double estimateMs, int64_t arrivalNs,
			   const char *mode, int trackId);

	Image<float> depthMm_;
	// The frame being answered.
	uint64_t frame_ = 0;
	int64_t arrivalNs_ = 0;
	PoseStageCounters counters_;
	bool interrupted_ = false;
	// The latest latencies (ms), for the stats percentiles.
	std::array<double, 1024> latencies_{};
	size_t latencyCount_ = 0;
};

} // namespace ihf::app
