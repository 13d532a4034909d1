// SPDX-License-Identifier: MIT
#pragma once

// Rigid model-to-camera transform, as BOP's cam_R_m2c / cam_t_m2c:
// x_cam = R x_model + t, t in millimetres.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ihf {

struct Pose {
	Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
	Eigen::Vector3d t = Eigen::Vector3d::Zero();

	Eigen::Vector3d apply(const Eigen::Vector3d &x) const { return R * x + t; }
	Pose inverse() const { return {R.transpose(), -R.transpose() * t}; }
	Pose operator*(const Pose &o) const { return {R * o.R, R * o.t + t}; }
};

// Angle in radians of the relative rotation between two rotations.
inline double rotationAngle(const Eigen::Matrix3d &a, const Eigen::Matrix3d &b)
{
	double c = ((a.transpose() * b).trace() - 1.0) * 0.5;
	c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
	return std::acos(c);
}

} // namespace ihf
