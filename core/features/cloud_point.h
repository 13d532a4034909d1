// SPDX-License-Identifier: MIT
#pragma once

// A back-projected depth pixel: camera-frame position (mm), the surface
// normal estimated from the depth image (unit, towards the camera; zero when
// it could not be estimated) and the pixel it came from.

#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

namespace ihf {

struct CloudPoint {
	Eigen::Vector3f p{0, 0, 0};
	Eigen::Vector3f n{0, 0, 0};
	int32_t u = 0;
	int32_t v = 0;

	bool hasNormal() const { return n.squaredNorm() > 0.25f; }
};

// Pixel rectangle [x, x + w) x [y, y + h).
struct PixelBox {
	int x = 0;
	int y = 0;
	int w = 0;
	int h = 0;

	bool empty() const { return w <= 0 || h <= 0; }
	bool contains(int u, int v) const { return u >= x && v >= y && u < x + w && v < y + h; }
};

// A detector's box [x, y, w, h] (fractional pixels) as the pixels every
// command estimates in: corner floored, size rounded up. ihf estimate and
// ihf run must agree on it to give the same poses.
inline PixelBox pixelsOfBox(const std::array<double, 4> &xywh)
{
	return {static_cast<int>(std::floor(xywh[0])), static_cast<int>(std::floor(xywh[1])),
		static_cast<int>(std::ceil(xywh[2])), static_cast<int>(std::ceil(xywh[3]))};
}

} // namespace ihf
