// SPDX-License-Identifier: MIT
#pragma once

// Evaluation of an implicit B-spline stored as an index-sorted list of active
// control points (what IbsFitter::fit writes), without the fitter's map:
// binary search per node column. For offline use and checks; the fitter's
// own evaluate() is the fast path.

#include <span>

#include <Eigen/Core>

#include "core/ibs/bspline_basis.h"
#include "core/ibs/control_point.h"

namespace ihf {

// f(x); if gradient is given it receives df/dx in unit-cube units.
float evaluateIbs(std::span<const ControlPoint> sortedCps, const Lattice &lattice,
		  const Eigen::Vector3f &x, Eigen::Vector3f *gradient = nullptr);

} // namespace ihf
