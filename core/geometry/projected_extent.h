// SPDX-License-Identifier: MIT
#pragma once

// The image box a mesh covers at a pose: the bounding box of the
// projections of at most ~512 evenly strided vertices (in float, the same
// bits on every target). What the score's box factor compares with the
// detector's box, and what a track's predicted silhouette is matched by.

#include <optional>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"

namespace ihf {

struct ProjectedExtent {
	float u0 = 0, v0 = 0, u1 = 0, v1 = 0; // pixels, [u0, u1] x [v0, v1]
};

// nullopt when the mesh is empty or a sampled vertex lies less than 1 mm
// in front of the camera (not a pose seen in the image).
std::optional<ProjectedExtent> projectedExtent(const Mesh &mesh, const Pose &pose, const CameraIntrinsics &K);

} // namespace ihf
