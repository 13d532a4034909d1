// SPDX-License-Identifier: MIT
#pragma once

// Test scenes of the sensor models: a plane turned away from the camera,
// and how much of it a sensor kept.

#include <cmath>
#include <numbers>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf::test {

// The plane z = z0 + tan(tiltDeg) X (through (0, 0, z0), turned about the
// camera's y axis), drawn where zMin < z < zMax.
inline DepthImageMm tiltedPlane(const CameraIntrinsics &K, double tiltDeg, double z0, double zMin, double zMax)
{
	DepthImageMm plane(K.width, K.height);
	const double slope = std::tan(tiltDeg * std::numbers::pi / 180);
	for (int y = 0; y < K.height; ++y)
		for (int x = 0; x < K.width; ++x) {
			// On the ray through (x, y): z = z0 / (1 - slope a), a = X / z.
			const double a = (x - K.cx) / K.fx;
			const double z = z0 / (1.0 - slope * a);
			plane.at(x, y) = (z > zMin && z < zMax) ? static_cast<float>(z) : 0.0f;
		}
	return plane;
}

struct Kept {
	int rendered = 0; // pixels with clean depth
	int valid = 0;    // pixels with sensor depth
};

// From column x0 on (a sensor's invalid left band left out).
inline Kept keptOf(const DepthImageMm &clean, const DepthImage16 &sensed, int x0 = 0)
{
	Kept k;
	for (int y = 0; y < clean.height(); ++y)
		for (int x = x0; x < clean.width(); ++x) {
			k.rendered += clean.at(x, y) > 0;
			k.valid += sensed.at(x, y) > 0;
		}
	return k;
}

} // namespace ihf::test
