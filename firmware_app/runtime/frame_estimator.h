// SPDX-License-Identifier: MIT
#pragma once

// The poses of one frame's boxes: the per-frame path of `ihf run` and of
// `ihf estimate` (with --sequence or without), so that both give the same
// poses for the same frames and boxes. Each box is looked up by its object
// id; a box whose object has no forest is answered without a pose and left
// out of the frame's budget. Without a tracker the boxes go one by one to
// the cold PoseEstimator and share the frame's budget; with a
// StreamEstimator the frame's boxes go to it together (tracked where a track
// holds, detected where needed, core/tracking/stream_estimator.h). Every box
// is answered through a BoxSink, in the order given.
// Nothing here allocates per frame: the tracker's box lists are fixed.

#include <array>
#include <cstdint>
#include <map>
#include <span>

#include "core/common/expected.h"
#include "core/estimation/pose_estimator.h"
#include "core/tracking/stream_estimator.h"
#include "drivers/clock.h"
#include "firmware_app/runtime/frame_box.h"

namespace ihf::app {

// Sees each cold estimation of a box (the --vis pictures, the --trace
// lines): begin() before the estimator runs (its hypotheses then go to the
// EstimateObserver the caller set on the estimator), end() after.
class BoxObserver
{
public:
	virtual ~BoxObserver() = default;
	virtual void begin(uint64_t frame, int objId, const PixelBox &box, ImageView<const float> depthMm,
			   const CameraIntrinsics &K, const ObjectModel &model) = 0;
	virtual void end(ImageView<const float> depthMm, const CameraIntrinsics &K, const ObjectModel &model,
			 const PoseEstimate &estimate) = 0;
};

// Takes each box's answer. model: the box's forest, null when its object
// has none (result.mode is then kSkipped, without a pose). Without a
// tracker every estimated box is a kDetect. An error stops the frame.
class BoxSink
{
public:
	virtual ~BoxSink() = default;
	virtual Status onBox(const FrameBox &box, const ObjectModel *model, const StreamResult &result) = 0;
};

class FrameEstimator
{
public:
	// models: the forests by object id; clock: times each cold box. Not
	// owned; config is copied.
	FrameEstimator(const std::map<int, const ObjectModel *> &models, PoseEstimator &estimator,
		       const EstimatorConfig &config, PacingClock &clock);

	// Frame-to-frame tracking (null: every box a cold estimate). Not owned;
	// on the estimator given above.
	void setTracker(StreamEstimator *tracker) { tracker_ = tracker; }
	void setBoxObserver(BoxObserver *observer) { observer_ = observer; }

	StreamEstimator *tracker() const { return tracker_; }
	PoseEstimator &estimator() const { return estimator_; }
	const EstimatorConfig &config() const { return config_; }
	const std::map<int, const ObjectModel *> &models() const { return models_; }
	const ObjectModel *model(int objId) const;

	// Under a frame budget the first frame's stages must be predicted from a
	// measurement, not taken as free: one synthetic box per object, at
	// frames of K's size. A problem is a note on stderr, prefixed `command`.
	void warmUp(const CameraIntrinsics &K, const char *command);

	// A new stream: every track ends.
	void beginStream();
	// A frame the detector saw nothing in: it ages the tracks.
	void skipFrame(uint64_t frame, const CameraIntrinsics &K);
	// The poses of the frame's boxes into sink, one call per box in order.
	// depthMm: the frame in millimetres; K: its intrinsics (of its size).
	Status estimate(uint64_t frame, ImageView<const float> depthMm, const CameraIntrinsics &K,
			std::span<const FrameBox> boxes, BoxSink &sink);

private:
	Status estimateCold(uint64_t frame, ImageView<const float> depthMm, const CameraIntrinsics &K,
			    std::span<const FrameBox> boxes, BoxSink &sink);
	Status estimateTracked(uint64_t frame, ImageView<const float> depthMm, const CameraIntrinsics &K,
			       std::span<const FrameBox> boxes, BoxSink &sink);

	std::map<int, const ObjectModel *> models_;
	PoseEstimator &estimator_;
	EstimatorConfig config_;
	PacingClock &clock_;
	StreamEstimator *tracker_ = nullptr;
	BoxObserver *observer_ = nullptr;
	// The tracked frame's boxes that have a forest, and their answers.
	std::array<StreamBox, StreamEstimator::kMaxBoxes> streamBoxes_{};
	std::array<StreamResult, StreamEstimator::kMaxBoxes> streamResults_{};
};

} // namespace ihf::app
