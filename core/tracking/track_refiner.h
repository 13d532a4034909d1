// SPDX-License-Identifier: MIT
#pragma once

// The tracked box: the track's predicted pose polished on the box's crop
// and checked (tracker_config.h). The crop is the same virtual on-axis
// window a detection scores in (virtual_crop.h), and the scorer and the ICP
// polisher are the detection's own (pose_scorer.h, icp_polisher.h), so a
// tracked score compares with the score the track was detected with. Its
// buffers are carved once from the caller's arena: refine() does not
// allocate.

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/estimation/hypothesis_score.h"
#include "core/estimation/pose_estimator.h"
#include "core/features/cloud_point.h"
#include "core/runtime/arena.h"
#include "core/tracking/tracker_config.h"

namespace ihf {

// Why a tracked pose was not kept (kKept: it was).
enum class TrackVerdict : uint8_t {
	kKept,
	kNoDepth,       // too few depth pixels in the box
	kOutsideBox,    // the prediction does not project into the box
	kNoFit,         // ICP found too few correspondences
	kLowScore,      // below minScore or keepShare of its detection's
	kLeftBox,       // box factor below minBoxFactor
	kJumped,        // the polish moved it too far from the prediction
	kRival,         // a half-turn scores as well
	kNoMemory,      // the window or mesh exceeds the refiner's buffers
};

const char *trackVerdictName(TrackVerdict verdict);

struct TrackRefinement {
	TrackVerdict verdict = TrackVerdict::kNoDepth;
	// found when kept. A pose that was scored but not kept (kNoFit,
	// kLowScore, kLeftBox, kJumped, kRival) is here too, with its score,
	// margin and confidence, and found false: the box's best guess while it
	// waits for a detection.
	PoseEstimate estimate;
	bool scored = false;
};

class TrackRefiner
{
public:
	// Arena bytes for windows of up to windowPixels and meshes of up to
	// maxMeshVertices.
	static size_t arenaBytes(int windowPixels, size_t maxMeshVertices);
	Status reserve(int windowPixels, size_t maxMeshVertices, Arena &arena);

	// The pose (model -> real camera) predicted for the box, polished and
	// checked against the track's detection score and margin.
	TrackRefinement refine(ImageView<const float> depth, const CameraIntrinsics &K, const PixelBox &box,
			       const ObjectModel &model, const EstimatorConfig &config, const TrackerConfig &tracking,
			       const Pose &predicted, float detectionScore, float detectionMargin);

private:
	template<typename A>
	bool carve(A &arena, size_t pixels);

	std::span<float> observed_, mask_, render_;
	std::span<CloudPoint> cloud_;
	DepthRenderer renderer_;
};

} // namespace ihf
