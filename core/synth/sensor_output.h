// SPDX-License-Identifier: MIT
#pragma once

// The last step of every depth sensor model: what the camera writes for a
// depth of v mm (0 = no depth).

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/synth/synth_random.h"

namespace ihf {

// 0 outside [minRangeMm, maxRangeMm] or for a pixel lost at random (one
// draw, only for a depth in range), else v in units of depthScale mm.
inline uint16_t sensorDepthValue(double v, double minRangeMm, double maxRangeMm, double pixelDropout,
				 SynthRandom &rng, double depthScale)
{
	if (v < minRangeMm || v > maxRangeMm || rng.uniform01() < pixelDropout)
		return 0;
	return static_cast<uint16_t>(std::min(std::round(v / depthScale), 65535.0));
}

} // namespace ihf
