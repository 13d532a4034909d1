// SPDX-License-Identifier: MIT
#pragma once

// Back-projection of a depth crop into a cloud with normals. Normals come
// from the cross product of central differences of the back-projected
// neighbours (falling back to one-sided differences at holes and depth
// discontinuities) and are turned towards the camera. Neighbours outside the
// box but inside the image are used, so crop borders get normals too.

#include <span>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/features/cloud_point.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf {

struct DepthCloudConfig {
	int normalStep = 2;        // pixels between the differenced neighbours
	float maxJumpMm = 10.0f;   // neighbours further apart in depth than
	float maxJumpRel = 0.02f;  //   max(maxJumpMm, maxJumpRel * z) per pixel step are
				   //   across a discontinuity
	int pixelStride = 1;       // take every k-th pixel in x and y
};

// Writes the valid pixels of box (clipped to the image) into out and returns
// how many; kCapacity if out is too small (out then holds the first
// out.size() points). depth is in mm, 0 = missing.
Expected<int> cloudFromDepth(ImageView<const float> depth, const CameraIntrinsics &intrinsics,
			     PixelBox box, const DepthCloudConfig &cfg, std::span<CloudPoint> out);

// Image box of a cloud's pixels (empty for an empty cloud).
PixelBox cloudPixelBox(std::span<const CloudPoint> cloud);

} // namespace ihf
