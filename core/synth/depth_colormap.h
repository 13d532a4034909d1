// SPDX-License-Identifier: MIT
#pragma once

// False-colour pictures of depth images for eyes: a blue (near) to red (far)
// ramp between two depths, missing depth in black (the ramp never reaches
// black).

#include <filesystem>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"

namespace ihf {

// RGB bytes, row-major. loMm >= hiMm picks the 2nd and 98th percentiles of
// the valid depths.
std::vector<uint8_t> depthFalseColour(const DepthImage16 &depth, double depthScale,
				      double loMm = 0, double hiMm = 0);

Status writeDepthPicture(const std::filesystem::path &file, const DepthImage16 &depth,
			 double depthScale, double loMm = 0, double hiMm = 0);

} // namespace ihf
