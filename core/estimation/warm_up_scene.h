// SPDX-License-Identifier: MIT
#pragma once

// The scene the estimator's warm-up estimates (PoseEstimator::warmUp()):
// the model alone in front of a wall, large in the window, so that every
// stage a budgeted box may run gets a measured cost before the first frame,
// and the first predictions err on the safe, high side.

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/model/object_model.h"
#include "core/render/depth_renderer.h"

namespace ihf {

struct WarmUpScene {
	Image<float> depth; // mm, the camera's size
	PixelBox box;       // a detector's box round the object
};

// The object across 80 % of the side of a window of maxWindowPixels, on the
// optical axis, turned so that no face is seen square on; a wall one
// diameter behind it gives the box a second depth slab, as a table or shelf
// does. The box is 10 % larger than the object's. Allocates the image: not
// for the frame path.
Expected<WarmUpScene> makeWarmUpScene(const ObjectModel &model, const CameraIntrinsics &K, int maxWindowPixels,
				      DepthRenderer &renderer);

} // namespace ihf
