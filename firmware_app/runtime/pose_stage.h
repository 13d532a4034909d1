// SPDX-License-Identifier: MIT
#pragma once

// What `ihf run` does with a frame: take its boxes from the BoxFeed,
// convert the raw depth to millimetres (as `ihf estimate` converts a BOP
// depth PNG, so both give the same poses), run the estimator on each box
// with its object's forest, and write a pose line, or an error line for a
// box whose object has no forest, a box without a pose, or a box line that
// did not parse; the other boxes go on. Buffers are sized in prepare().
// With a StreamEstimator the frame's boxes go to it instead (tracked where
// a track holds, detected where needed, core/tracking/stream_estimator.h),
// and every line carries the box's mode and track.

#include <array>
#include <chrono>
#include <cstdio>
#include <map>
#include <vector>

#include "core/estimation/pose_estimator.h"
#include "core/tracking/stream_estimator.h"
#include "drivers/clock.h"
#include "firmware_app/runtime/box_feed.h"
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

// Sees each box's estimation (the --vis pictures): begin() before the
// estimator runs (its hypotheses then go to the EstimateObserver the caller
// set on the estimator), end() after.
class BoxObserver
{
public:
	virtual ~BoxObserver() = default;
	virtual void begin(uint64_t frame, int objId, const PixelBox &box) = 0;
	virtual void end(ImageView<const float> depthMm, const CameraIntrinsics &K,
			 const ObjectModel &model, const PoseEstimate &estimate) = 0;
};

class PoseStage : public FrameProcessor
{
public:
	PoseStage(std::map<int, const ObjectModel *> models, PoseEstimator &estimator,
		  const EstimatorConfig &config, BoxFeed &feed, PoseOutput &output, PacingClock &clock,
		  std::chrono::milliseconds boxesTimeout);

	void setBoxObserver(BoxObserver *observer) { observer_ = observer; }
	// Frame-to-frame tracking (null: every box a cold estimate). Not owned;
	// on the estimator given above.
	void setTracker(StreamEstimator *tracker) { tracker_ = tracker; }

	Status prepare(const SourceInfo &info) override;
	Status process(const Frame &frame, int64_t arrivalNs) override;
	void describe(std::string &line) const override;
	bool interrupted() const override { return interrupted_; }

	const PoseStageCounters &counters() const { return counters_; }

private:
	std::map<int, const ObjectModel *> models_;
	PoseEstimator &estimator_;
	EstimatorConfig config_;
	BoxFeed &feed_;
	PoseOutput &output_;
	PacingClock &clock_;
	std::chrono::milliseconds boxesTimeout_;
	Status processTracked(const Frame &frame, const CameraIntrinsics &K, int64_t arrivalNs);
	Status writeUnknownObject(uint64_t frame, int objId);
	Status writeResult(uint64_t frame, int objId, const PoseEstimate &e, double estimateMs, int64_t arrivalNs,
			   const char *mode, int trackId);

	BoxObserver *observer_ = nullptr;
	StreamEstimator *tracker_ = nullptr;
	std::array<StreamBox, StreamEstimator::kMaxBoxes> streamBoxes_{};
	std::array<StreamResult, StreamEstimator::kMaxBoxes> streamResults_{};
	Image<float> depthMm_;
	PoseStageCounters counters_;
	bool interrupted_ = false;
	// The latest latencies (ms), for the stats percentiles.
	std::array<double, 1024> latencies_{};
	size_t latencyCount_ = 0;
};

} // namespace ihf::app
