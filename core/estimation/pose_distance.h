// SPDX-License-Identifier: MIT
#pragma once

// How far apart two poses lie, measured as the evaluation measures a pose
// error: the mean distance between the model's points placed by each. At
// most kPoseDistancePoints of the model's vertices, evenly strided, stand
// for the model. The confidence's rivals (rival_poses.h) and the turns
// about a near-symmetry (symmetry_rivals.h) are told apart this way.

#include <span>

#include <Eigen/Core>

#include "core/geometry/pose.h"

namespace ihf {

inline constexpr int kPoseDistancePoints = 64;

// At most kPoseDistancePoints of vertices, evenly strided, into out;
// returns how many.
int sampleModelPoints(std::span<const Eigen::Vector3f> vertices,
		      std::span<Eigen::Vector3d, kPoseDistancePoints> out);

// The mean distance (mm) between the points placed by a and by b; 0 for no
// points.
double meanPointDistance(const Pose &a, const Pose &b, std::span<const Eigen::Vector3d> points);

} // namespace ihf
