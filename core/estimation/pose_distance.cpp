// SPDX-License-Identifier: MIT
#include "core/estimation/pose_distance.h"

namespace ihf {

int sampleModelPoints(std::span<const Eigen::Vector3f> vertices,
		      std::span<Eigen::Vector3d, kPoseDistancePoints> out)
{
	int n = 0;
	const size_t stride = (vertices.size() + kPoseDistancePoints - 1) / kPoseDistancePoints;
	for (size_t i = 0; i < vertices.size() && n < kPoseDistancePoints; i += stride)
		out[static_cast<size_t>(n++)] = vertices[i].cast<double>();
	return n;
}

double meanPointDistance(const Pose &a, const Pose &b, std::span<const Eigen::Vector3d> points)
{
	if (points.empty())
		return 0;
	const Eigen::Matrix3d dR = a.R - b.R;
	const Eigen::Vector3d dt = a.t - b.t;
	double sum = 0;
	for (const Eigen::Vector3d &p : points)
		sum += (dR * p + dt).norm();
	return sum / static_cast<double>(points.size());
}

} // namespace ihf
