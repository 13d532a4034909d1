// SPDX-License-Identifier: MIT
#pragma once

// A fixed set of rotations covering SO(3): the training views' layout
// (Fibonacci viewing directions x evenly spaced in-plane turns), generated
// on demand without memory. Used to verify every coarse rotation at a voted
// translation when the forest's rotation votes are weak (issue 3: about 1 %
// of the votes lie within 20 deg of the true rotation on occluded boxes).

#include <Eigen/Core>

namespace ihf {

struct RotationBankConfig {
	int viewpoints = 0; // 0: off
	int inplane = 8;
	int centres = 2;    // distinct best translations searched
	int keep = 4;       // best bank hypotheses per translation kept for the polish
};

inline int rotationBankSize(const RotationBankConfig &c)
{
	return c.viewpoints > 0 && c.inplane > 0 ? c.viewpoints * c.inplane : 0;
}

// Rotation i (model -> camera) of the bank, 0 <= i < rotationBankSize(c).
Eigen::Matrix3d rotationBankEntry(const RotationBankConfig &c, int i);

} // namespace ihf
