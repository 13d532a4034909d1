// SPDX-License-Identifier: MIT
#pragma once

// Closed solids for procedural object meshes: surfaces of revolution,
// tubes swept along a path and boxes, each a closed shell with shared
// corners wound outwards, appended into one mesh (the shells may overlap:
// the depth renderer sees their union). Millimetres; no vertex normals.

#include <span>

#include <Eigen/Core>

#include "core/geometry/mesh.h"

namespace ihf {

// The surface of revolution about +z of a profile of (radius, z) points
// that starts and ends on the axis (radius 0): the profile's polygon, closed
// by the axis, turned full round in `segments` steps.
Mesh makeLathe(std::span<const Eigen::Vector2d> profile, int segments = 48);

// A tube of the given radius swept along a path (at least two points),
// closed by flat caps at both ends. `up` is a direction never parallel to
// the path: the cross-section's rings are kept square to it.
Mesh makeTube(std::span<const Eigen::Vector3d> path, double radius, const Eigen::Vector3d &up,
	      int segments = 16);

// An axis-aligned box between two corners, eight shared corners.
Mesh makeSolidBox(const Eigen::Vector3d &lo, const Eigen::Vector3d &hi);

// Applies x -> R x + t to every vertex.
void transformMesh(Mesh &mesh, const Eigen::Matrix3d &R, const Eigen::Vector3d &t);

// Appends `part` to `mesh` (its own shell, indices shifted).
void appendMesh(Mesh &mesh, const Mesh &part);

} // namespace ihf
