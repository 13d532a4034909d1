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

int halfTurnCount(const HalfTurnConfig &c)
{
	return c.axes + (c.boxAxes ? 3 : 0);
}

Eigen::Matrix3d halfTurnOf(const HalfTurnConfig &c, int i)
{
	if (i < c.axes)
		return halfTurn(i, c.axes);
	// About axis i - axes of the model frame: 2 e e^T - I.
	Eigen::Matrix3d turn = -Eigen::Matrix3d::Identity();
	turn(i - c.axes, i - c.axes) = 1.0;
	return turn;
}

Pose turnedAbout(const Pose &pose, const Eigen::Matrix3d &turn, const Eigen::Vector3d &centre)
{
	Pose out;
	out.R = pose.R * turn;
	out.t = pose.t + pose.R * centre - out.R * centre;
	return out;
}

} // namespace ihf
