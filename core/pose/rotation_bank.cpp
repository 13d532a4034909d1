// SPDX-License-Identifier: MIT
#include "core/pose/rotation_bank.h"

#include <cmath>

#include "core/geometry/rotation.h"

namespace ihf {

Eigen::Matrix3d rotationBankEntry(const RotationBankConfig &c, int i)
{
	const int view = i / c.inplane, turn = i % c.inplane;
	return lookAtRotation(fibonacciDirection(view, c.viewpoints), 2.0 * M_PI * turn / c.inplane);
}

} // namespace ihf
