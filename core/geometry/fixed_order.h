// SPDX-License-Identifier: MIT
#pragma once

// Small float products written out in one summation order. Eigen may
// vectorise a 3x3 product or a 3-vector sum differently per target (SSE
// has no 2-float packet, NEON has), so the last bits of a result, and what
// a search decides on them, could differ between amd64 and ARM. Used where
// a test showed such a difference (tests/estimation/test_golden_pose).

#include <Eigen/Core>

namespace ihf {

// R x + t, each row summed left to right.
inline Eigen::Vector3f transformFixedOrder(const Eigen::Matrix3f &R, const Eigen::Vector3f &x,
					   const Eigen::Vector3f &t)
{
	Eigen::Vector3f y;
	for (int r = 0; r < 3; ++r)
		y[r] = ((R(r, 0) * x[0] + R(r, 1) * x[1]) + R(r, 2) * x[2]) + t[r];
	return y;
}

// a . b summed x, y, z in that order.
inline float dotFixedOrder(const Eigen::Vector3f &a, const Eigen::Vector3f &b)
{
	return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
}

inline Eigen::Vector3f crossFixedOrder(const Eigen::Vector3f &a, const Eigen::Vector3f &b)
{
	return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

} // namespace ihf
