// SPDX-License-Identifier: MIT
#pragma once

// Parts leave the extractor in unit-cube units; training and inference both
// move them to millimetres so that the forest's depth check compares
// physical depths whatever the scale-space factor. The HoCP does not change:
// it depends only on ratios of radii and on directions.

#include <span>

#include "core/features/hocp.h"
#include "core/features/part.h"

namespace ihf {

inline void partToMillimetres(std::span<PartCp> cps, float &zMin, float &zMax, float mmPerUnit,
			      const HocpConfig &hocp)
{
	for (auto &cp : cps)
		cp.rel *= mmPerUnit;
	zMin *= mmPerUnit;
	zMax *= mmPerUnit;
	setHocpKeys(cps, hocp);
}

} // namespace ihf
