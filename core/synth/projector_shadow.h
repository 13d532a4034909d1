// SPDX-License-Identifier: MIT
#pragma once

// Structured-light shadows. The Kinect v1's IR projector sits a baseline
// (~75 mm) beside the IR camera along the camera's x axis; points the camera
// sees but the projector's pattern cannot reach get no depth. With the
// projector at +b on x and the same orientation, a camera pixel (u, v) at
// depth z is lit by projector column u - fx b / z on the same row: it is in
// shadow when the projector's own depth buffer holds something nearer there.
// The shadow falls on the side of a foreground edge away from the projector
// (left of objects in the image for +b).

#include <vector>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf {

// projectorDepth is the scene rendered from the projector (see
// SceneRenderer::projectorView) into a buffer whose pixel (0, 0) is image
// pixel (projectorX0, 0). Returns 1 where the camera pixel is unlit.
std::vector<uint8_t> projectorShadow(ImageView<const float> cameraDepth,
				     ImageView<const float> projectorDepth, int projectorX0,
				     const CameraIntrinsics &K, double baselineMm,
				     double toleranceMm = 8.0, double toleranceRel = 0.01);

// Columns the projector buffer must reach left of the image for the nearest
// depth minDepthMm (its x0 is minus this).
int projectorPadding(const CameraIntrinsics &K, double baselineMm, double minDepthMm);

} // namespace ihf
