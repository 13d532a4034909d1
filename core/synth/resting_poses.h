// SPDX-License-Identifier: MIT
#pragma once

// Physically plausible resting poses of a rigid mesh on a horizontal plane.
// A body can rest on a facet of its convex hull when its centre of mass
// projects inside that facet (a stable facet). A dropped body rolls until
// its centre of mass is at a local minimum of the height
// H(d) = max_v d.v - d.c over "down" directions d, so the probability of a
// facet is the share of the sphere of directions whose descent on H ends
// there (sampled on a Fibonacci lattice), as for a random drop.

#include <vector>

#include <Eigen/Core>

#include "core/common/expected.h"
#include "core/geometry/mesh.h"

namespace ihf {

struct RestingPose {
	// Model -> rest frame: the table normal is +z, the model lies above the
	// plane z = min.z(), the yaw about z is free.
	Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
	double probability = 1.0;
	// Axis-aligned box of the rotated model in the rest frame (mm).
	Eigen::Vector3d min = Eigen::Vector3d::Zero();
	Eigen::Vector3d max = Eigen::Vector3d::Zero();
};

// Centre of mass of a closed mesh (uniform density, divergence theorem);
// the vertex mean when the mesh encloses no volume.
Eigen::Vector3d centreOfMass(const Mesh &mesh);

// Stable poses sorted by decreasing probability (they sum to 1). directions
// is the resolution of the sphere sampling. Poses that catch fewer than
// minProbability of the drops are discarded.
Expected<std::vector<RestingPose>> computeRestingPoses(const Mesh &mesh, int directions = 2000,
						       double minProbability = 0.01);

// Axis-aligned box of R * v over the mesh vertices.
void rotatedBounds(const Mesh &mesh, const Eigen::Matrix3d &R, Eigen::Vector3d &min,
		   Eigen::Vector3d &max);

} // namespace ihf
