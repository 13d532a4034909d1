// SPDX-License-Identifier: MIT
#pragma once

// Convex hull of a point set via Qhull (libqhull_r): its facets as planes
// with their vertices. Nearly coplanar triangles are merged into one facet,
// so a flat base made of many small triangles is one polygon.

#include <vector>

#include <Eigen/Core>

#include "core/common/expected.h"

namespace ihf {

struct HullFacet {
	Eigen::Vector3d normal = Eigen::Vector3d::Zero(); // unit, outward
	double offset = 0; // normal . x = offset on the facet's plane
	std::vector<Eigen::Vector3d> vertices;
};

// mergeDistance (point units) merges facets whose centrums lie within it of
// their neighbours' planes.
Expected<std::vector<HullFacet>> convexHull(const std::vector<Eigen::Vector3d> &points,
					    double mergeDistance = 0.5);

} // namespace ihf
