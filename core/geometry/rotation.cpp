// SPDX-License-Identifier: MIT
#include "core/geometry/rotation.h"

namespace ihf {

Eigen::Matrix3d rotationBetween(const Eigen::Vector3d &from, const Eigen::Vector3d &to)
{
	return Eigen::Quaterniond::FromTwoVectors(from, to).toRotationMatrix();
}

Eigen::Matrix3d lookAtRotation(const Eigen::Vector3d &viewDir, double inplane)
{
	// Camera axes in model coordinates: z looks from the camera at the
	// origin, so it is -viewDir; x and y complete a right-handed frame with y
	// pointing "down" as in image coordinates.
	Eigen::Vector3d z = -viewDir.normalized();
	Eigen::Vector3d up = std::abs(z.z()) < 0.99 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
	Eigen::Vector3d x = up.cross(z).normalized();
	Eigen::Vector3d y = z.cross(x);
	Eigen::Matrix3d camFromModel;
	camFromModel.row(0) = x;
	camFromModel.row(1) = y;
	camFromModel.row(2) = z;
	Eigen::Matrix3d roll = Eigen::AngleAxisd(inplane, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	return roll * camFromModel;
}

Eigen::Vector3d fibonacciDirection(int i, int count)
{
	const double golden = M_PI * (3.0 - std::sqrt(5.0));
	const double z = 1.0 - (2.0 * i + 1.0) / count;
	const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
	const double a = golden * i;
	return {r * std::cos(a), r * std::sin(a), z};
}

std::vector<Eigen::Vector3d> fibonacciSphere(int count)
{
	std::vector<Eigen::Vector3d> dirs;
	dirs.reserve(count);
	for (int i = 0; i < count; ++i)
		dirs.push_back(fibonacciDirection(i, count));
	return dirs;
}

} // namespace ihf
