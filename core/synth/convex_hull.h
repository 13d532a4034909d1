// SPDX-License-Identifier: MIT
#pragma once

// Convex hull of a point set via Qhull (libqhull_r): its facets as planes
// with their vertices.

#include <vector>

#include <Eigen/Core>

#include "core/common/expected.h"

namespace ihf {

struct HullFacet {
	Eigen::Vector3d normal = Eigen::Vector3d::Zero(); // unit, outward
	double offset = 0; // normal . x = offset on the facet's plane
	std::vector<Eigen::Vector3d> vertices;
};

// mergeDistance > 0 (point units) also merges facets whose centrums lie
// within it of their neighbours' planes (larger, but inexact, facets); 0
// keeps Qhull's default of merging only what is coplanar within roundoff,
// so every point lies on or below every facet plane.
Expected<std::vector<HullFacet>> convexHull(const std::vector<Eigen::Vector3d> &points,
					    double mergeDistance = 0.0);

} // namespace ihf
