// SPDX-License-Identifier: MIT
#pragma once

// An active control point of a fitted implicit B-spline: the (index, weight)
// descriptor of Sect. III-A, with the node's unit-cube position kept beside
// the index so that parts need no lattice arithmetic.

#include <cstdint>

#include <Eigen/Core>

namespace ihf {

struct ControlPoint {
	int32_t index = 0;        // (i * N + j) * N + k, i along x, k along z
	Eigen::Vector3f pos{0, 0, 0}; // node position in the unit cube
	float weight = 0;         // fitted control value n_ijk
};

} // namespace ihf
