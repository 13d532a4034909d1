// SPDX-License-Identifier: MIT
#pragma once

// Pinhole intrinsics, OpenCV/BOP convention: pixel (u, v) has its centre at
// integer coordinates, u = fx X / Z + cx, v = fy Y / Z + cy, Z forward.

#include <Eigen/Core>

namespace ihf {

struct CameraIntrinsics {
	double fx = 0, fy = 0, cx = 0, cy = 0;
	int width = 0, height = 0;

	bool valid() const { return fx > 0 && fy > 0 && width > 0 && height > 0; }

	Eigen::Vector2d project(const Eigen::Vector3d &p) const
	{
		return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
	}

	// Back-project pixel (u, v) at metric depth z (same unit as the result).
	Eigen::Vector3d backProject(double u, double v, double z) const
	{
		return {(u - cx) * z / fx, (v - cy) * z / fy, z};
	}

	Eigen::Matrix3d matrix() const
	{
		Eigen::Matrix3d k;
		k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
		return k;
	}
};

// Kinect v1 as calibrated for LINEMOD / Occluded-LINEMOD (BOP camera.json):
// the default camera of training and synthesis.
inline CameraIntrinsics kinectV1Intrinsics()
{
	return CameraIntrinsics{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};
}

} // namespace ihf
