// SPDX-License-Identifier: MIT
#pragma once

// The hypothesis scorer that detection (PoseEstimator) and tracking
// (core/tracking) share: a pose is rendered into the caller's buffer and
// scored against the observed window (hypothesis_score.h), its depth
// agreement times its agreement with the window's box. The window is the
// box's virtual crop, so a tracked pose and a detected one are scored alike
// and their scores compare.

#include "core/common/image.h"
#include "core/estimation/hypothesis_score.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/open_sides.h"
#include "core/geometry/pose.h"
#include "core/model/object_model.h"
#include "core/render/depth_renderer.h"

namespace ihf {

// Where a pose is scored: the observed window, its sides that lie on the
// frame's border (open to overhang) and the score's weights.
struct ScoreWindow {
	ImageView<const float> observed;
	CameraIntrinsics K; // of the window
	OpenSides open;
	const ScoreConfig *config = nullptr;
	int downsample = 1; // sensor pixels to a window pixel
};

// The pose rendered with the model's render mesh into `render` (cleared
// first); false if the render failed.
bool renderModel(DepthRenderer &renderer, ImageView<float> render, const ObjectModel &model, const Pose &pose,
		 const CameraIntrinsics &K);

// The pose's score in the window (a zero score when it cannot be rendered).
// `render` holds the pose's depth afterwards.
HypothesisScore scoreInWindow(const ScoreWindow &window, DepthRenderer &renderer, ImageView<float> render,
			      const ObjectModel &model, const Pose &pose);

} // namespace ihf
