// SPDX-License-Identifier: MIT
#pragma once

// Angle between the surface normal and the viewing ray at every pixel of a
// clean depth image, and which pixels sit on a depth discontinuity. Normals
// come from the back-projected neighbours, taking on each axis the one-sided
// difference with the smaller depth step so a neighbouring surface behind or
// in front does not bend the normal.

#include <vector>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf {

struct IncidenceMap {
	int width = 0, height = 0;
	std::vector<float> angle; // radians in [0, pi/2]; pi/2 where unknown
	std::vector<uint8_t> edge; // 1 next to a jump larger than the threshold

	float angleAt(int x, int y) const { return angle[static_cast<size_t>(y) * width + x]; }
	bool edgeAt(int x, int y) const { return edge[static_cast<size_t>(y) * width + x] != 0; }
};

// A neighbour differing by more than max(jumpMm, jumpRel * z) is across an edge.
IncidenceMap computeIncidence(ImageView<const float> depth, const CameraIntrinsics &K,
			      double jumpMm = 15.0, double jumpRel = 0.02);

} // namespace ihf
