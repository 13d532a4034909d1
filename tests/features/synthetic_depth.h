// SPDX-License-Identifier: MIT
#pragma once

// Analytic depth images for the feature tests: planes and spheres ray-cast
// exactly (depth = camera Z in mm, 0 where nothing is hit).

#include <cmath>

#include <Eigen/Core>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf::test {

inline CameraIntrinsics lmoIntrinsics()
{
	CameraIntrinsics k;
	k.fx = 572.4114;
	k.fy = 573.57043;
	k.cx = 325.2611;
	k.cy = 242.04899;
	k.width = 640;
	k.height = 480;
	return k;
}

inline Eigen::Vector3d rayOf(const CameraIntrinsics &k, int u, int v)
{
	return {(u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0};
}

// Plane n . X = d (n unit; d = n . p for a point p on it) into depth where
// the plane is nearer than what is there (or where depth is 0).
inline void drawPlane(ImageView<float> depth, const CameraIntrinsics &k, const Eigen::Vector3d &n,
		      double d)
{
	for (int v = 0; v < depth.height; ++v)
		for (int u = 0; u < depth.width; ++u) {
			const double den = n.dot(rayOf(k, u, v));
			if (std::abs(den) < 1e-9)
				continue;
			const double z = d / den;
			float &px = depth.at(u, v);
			if (z > 0 && (px == 0.0f || z < px))
				px = static_cast<float>(z);
		}
}

inline void drawSphere(ImageView<float> depth, const CameraIntrinsics &k, const Eigen::Vector3d &c,
		       double radius)
{
	for (int v = 0; v < depth.height; ++v)
		for (int u = 0; u < depth.width; ++u) {
			const Eigen::Vector3d r = rayOf(k, u, v);
			// |t r - c|^2 = R^2, nearest root; Z of the hit is t.
			const double a = r.squaredNorm(), b = -2.0 * r.dot(c);
			const double cc = c.squaredNorm() - radius * radius;
			const double disc = b * b - 4 * a * cc;
			if (disc < 0)
				continue;
			const double z = (-b - std::sqrt(disc)) / (2 * a);
			float &px = depth.at(u, v);
			if (z > 0 && (px == 0.0f || z < px))
				px = static_cast<float>(z);
		}
}

} // namespace ihf::test
