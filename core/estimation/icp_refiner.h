// SPDX-License-Identifier: MIT
#pragma once

// A final polish, not part of the paper (NOTES §6: measured separately):
// projective point-to-plane ICP between the observed cloud and the model
// rendered at the current pose. Correspondences are the rendered model
// point at the same pixel; the update rotates about the model origin, which
// keeps the 6x6 system well conditioned at a metre's distance.

#include <span>

#include "core/common/image.h"
#include "core/features/cloud_point.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"
#include "core/render/depth_renderer.h"

namespace ihf {

struct IcpConfig {
	int iterations = 10;
	float maxDistanceMm = 25.0f; // first iteration's gate
	float minDistanceMm = 8.0f;  // last iteration's gate
	int minCorrespondences = 30;
	// Render the model once, at the start pose, and associate later
	// iterations through the pose change since (the model's surface as
	// first seen, moved rigidly: a small update hardly changes what is
	// visible). false: a render every iteration.
	bool renderOnce = false;
};

struct IcpResult {
	Pose pose;
	int iterations = 0;
	int correspondences = 0;
	float rmsMm = 0;
};

// cloud: observed points (pixels in the window of `K`), with normals.
// render: scratch of K.width x K.height floats.
IcpResult refineIcp(std::span<const CloudPoint> cloud, const Mesh &mesh, const Pose &start,
		    const CameraIntrinsics &K, DepthRenderer &renderer, ImageView<float> render,
		    const IcpConfig &config);

} // namespace ihf
