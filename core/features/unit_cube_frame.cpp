// SPDX-License-Identifier: MIT

#include "core/features/unit_cube_frame.h"

#include <algorithm>
#include <limits>

namespace ihf {

Expected<UnitCubeFrame> makeUnitCubeFrame(std::span<const CloudPoint> cloud, float scale,
					  CubeCentre centre)
{
	if (cloud.empty())
		return makeError(Errc::kInvalidArgument, "makeUnitCubeFrame: empty cloud");
	if (!(scale > 0.0f))
		return makeError(Errc::kInvalidArgument, "makeUnitCubeFrame: scale must be > 0");

	Eigen::Vector3f lo = cloud[0].p, hi = cloud[0].p;
	// Double accumulation keeps the mean exact enough for translation tests.
	Eigen::Vector3d sum = Eigen::Vector3d::Zero();
	for (const CloudPoint &c : cloud) {
		lo = lo.cwiseMin(c.p);
		hi = hi.cwiseMax(c.p);
		sum += c.p.cast<double>();
	}
	UnitCubeFrame frame;
	frame.alpha = (hi - lo).maxCoeff();
	if (!(frame.alpha > 0.0f))
		return makeError(Errc::kInvalidArgument, "makeUnitCubeFrame: cloud has no extent");
	frame.scale = scale;
	if (centre == CubeCentre::kMean)
		frame.centre = (sum / static_cast<double>(cloud.size())).cast<float>();
	else
		frame.centre = 0.5f * (lo + hi);
	return frame;
}

void toUnitCube(std::span<const CloudPoint> cloud, const UnitCubeFrame &frame,
		std::span<Eigen::Vector3f> outPoints, std::span<Eigen::Vector3f> outNormals)
{
	const float inv = 1.0f / frame.mmPerUnit();
	const size_t n = std::min(cloud.size(), outPoints.size());
	for (size_t i = 0; i < n; ++i)
		outPoints[i] = (cloud[i].p - frame.centre) * inv + Eigen::Vector3f::Constant(0.5f);
	const size_t m = std::min(cloud.size(), outNormals.size());
	for (size_t i = 0; i < m; ++i)
		outNormals[i] = cloud[i].n;
}

float depthExtent(std::span<const Eigen::Vector3f> unitPoints)
{
	if (unitPoints.empty())
		return 0.0f;
	float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
	for (const Eigen::Vector3f &p : unitPoints) {
		lo = std::min(lo, p.z());
		hi = std::max(hi, p.z());
	}
	return hi - lo;
}

} // namespace ihf
