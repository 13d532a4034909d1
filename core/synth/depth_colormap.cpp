// SPDX-License-Identifier: MIT
#include "core/synth/depth_colormap.h"

#include <algorithm>
#include <cmath>

#include "core/dataset/bop_io.h"

namespace ihf {

std::vector<uint8_t> depthFalseColour(const DepthImage16 &depth, double depthScale, double loMm,
				      double hiMm)
{
	if (loMm >= hiMm) {
		std::vector<uint16_t> valid;
		for (uint16_t v : depth.pixels())
			if (v > 0)
				valid.push_back(v);
		if (!valid.empty()) {
			std::sort(valid.begin(), valid.end());
			loMm = valid[valid.size() * 2 / 100] * depthScale;
			hiMm = valid[valid.size() * 98 / 100] * depthScale;
		}
		if (loMm >= hiMm)
			hiMm = loMm + 1.0;
	}
	std::vector<uint8_t> rgb(static_cast<size_t>(depth.width()) * depth.height() * 3, 0);
	auto channel = [](double t, double centre) {
		return static_cast<uint8_t>(255.0 * std::clamp(1.5 - std::abs(4.0 * t - centre), 0.0, 1.0));
	};
	for (int y = 0; y < depth.height(); ++y) {
		for (int x = 0; x < depth.width(); ++x) {
			const uint16_t v = depth.at(x, y);
			if (v == 0)
				continue;
			const double t = std::clamp((v * depthScale - loMm) / (hiMm - loMm), 0.0, 1.0);
			uint8_t *p = &rgb[(static_cast<size_t>(y) * depth.width() + x) * 3];
			p[0] = channel(t, 3.0);
			p[1] = channel(t, 2.0);
			p[2] = channel(t, 1.0);
		}
	}
	return rgb;
}

Status writeDepthPicture(const std::filesystem::path &file, const DepthImage16 &depth,
			 double depthScale, double loMm, double hiMm)
{
	const std::vector<uint8_t> rgb = depthFalseColour(depth, depthScale, loMm, hiMm);
	return writePng8(file, depth.width(), depth.height(), 3, rgb.data());
}

} // namespace ihf
