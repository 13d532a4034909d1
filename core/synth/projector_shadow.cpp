// SPDX-License-Identifier: MIT
#include "core/synth/projector_shadow.h"

#include <algorithm>
#include <cmath>

namespace ihf {

int projectorPadding(const CameraIntrinsics &K, double baselineMm, double minDepthMm)
{
	return static_cast<int>(std::ceil(K.fx * baselineMm / std::max(minDepthMm, 1.0))) + 2;
}

std::vector<uint8_t> projectorShadow(ImageView<const float> cameraDepth,
				     ImageView<const float> projectorDepth, int projectorX0,
				     const CameraIntrinsics &K, double baselineMm,
				     double toleranceMm, double toleranceRel)
{
	const int W = cameraDepth.width, H = cameraDepth.height;
	std::vector<uint8_t> shadow(static_cast<size_t>(W) * H, 0);
	const double fb = K.fx * baselineMm;
	for (int y = 0; y < H && y < projectorDepth.height; ++y) {
		for (int x = 0; x < W; ++x) {
			const float z = cameraDepth.at(x, y);
			if (z <= 0.0f)
				continue;
			const int up = static_cast<int>(std::lround(x - fb / z)) - projectorX0;
			if (up < 0 || up >= projectorDepth.width) {
				// Outside the projector's field: no pattern there either.
				shadow[static_cast<size_t>(y) * W + x] = 1;
				continue;
			}
			const float zp = projectorDepth.at(up, y);
			const double tol = std::max(toleranceMm, toleranceRel * z);
			if (zp > 0.0f && zp < z - tol)
				shadow[static_cast<size_t>(y) * W + x] = 1;
		}
	}
	return shadow;
}

} // namespace ihf
