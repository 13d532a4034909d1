// SPDX-License-Identifier: MIT
#pragma once

// Rotation helpers shared by training (view sampling) and inference (vote
// modes, virtual on-axis camera).

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ihf {

// An angle in degrees, in radians.
inline double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

// <q1, q2> summed x, y, z, w in that order (Eigen's 4-float dot adds in
// another order with SIMD than without, e.g. on armhf).
inline float quatDot(const Eigen::Quaternionf &a, const Eigen::Quaternionf &b)
{
	return ((a.x() * b.x() + a.y() * b.y()) + a.z() * b.z()) + a.w() * b.w();
}

// Quaternions q and -q are the same rotation: similarity is |<q1, q2>|.
inline float quatSimilarity(const Eigen::Quaternionf &a, const Eigen::Quaternionf &b)
{
	return std::abs(quatDot(a, b));
}

// Geodesic angle (radians) between two rotations given as unit quaternions.
inline float quatAngle(const Eigen::Quaternionf &a, const Eigen::Quaternionf &b)
{
	float c = quatSimilarity(a, b);
	// acos in double: glibc's acosf differs between amd64 and aarch64.
	return 2.0f * static_cast<float>(std::acos(static_cast<double>(c > 1.0f ? 1.0f : c)));
}

// The minimal rotation taking unit-direction `from` onto `to`
// (Eigen's FromTwoVectors). Out of line: its opposite-vectors case
// instantiates a JacobiSVD, ~10 s of compile time in every includer.
Eigen::Matrix3d rotationBetween(const Eigen::Vector3d &from, const Eigen::Vector3d &to);

// Rotation taking the optical axis (0,0,1) onto the unit ray `dir`, with no
// twist about the axis (the minimal rotation). Used to turn a crop into a
// virtual camera looking straight at it.
inline Eigen::Matrix3d rayAlignment(const Eigen::Vector3d &dir)
{
	return rotationBetween(Eigen::Vector3d::UnitZ(), dir.normalized());
}

// Camera-from-model rotation for a camera on the unit sphere direction
// `viewDir` (from the object towards the camera) looking at the object's
// origin, rotated in-plane by `inplane` radians about the optical axis.
Eigen::Matrix3d lookAtRotation(const Eigen::Vector3d &viewDir, double inplane);

// Direction i of a Fibonacci lattice of count points (no allocation).
Eigen::Vector3d fibonacciDirection(int i, int count);

// Quasi-uniform directions on the sphere (Fibonacci lattice).
std::vector<Eigen::Vector3d> fibonacciSphere(int count);

} // namespace ihf
