// SPDX-License-Identifier: MIT
#include "core/pose/half_turns.h"

#include "core/geometry/rotation.h"

namespace ihf {

Eigen::Matrix3d halfTurn(int i, int count)
{
	// The first half of a Fibonacci lattice of 2 count points is the upper
	// hemisphere. A half-turn about unit a is 2 a a^T - I.
	const Eigen::Vector3d a = fibonacciDirection(i, 2 * count).normalized();
	return 2.0 * a * a.transpose() - Eigen::Matrix3d::Identity();
}

Pose turnedAbout(const Pose &pose, const Eigen::Matrix3d &turn, const Eigen::Vector3d &centre)
{
	Pose out;
	out.R = pose.R * turn;
	out.t = pose.t + pose.R * centre - out.R * centre;
	return out;
}

} // namespace ihf
