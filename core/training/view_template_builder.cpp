// SPDX-License-Identifier: MIT
#include "core/training/view_template_builder.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/pose.h"
#include "core/geometry/rotation.h"
#include "core/render/depth_renderer.h"

namespace ihf {

Expected<std::vector<Eigen::Vector3f>> buildViewTemplatePoints(const Mesh &mesh, double diameter,
							       const ViewTemplateConfig &config)
{
	if (config.viewpoints <= 0 || config.pointsPerView <= 0)
		return makeError(Errc::kInvalidArgument, "view templates: viewpoints and points per view must be positive");
	if (!(diameter > 0) || mesh.faces.empty())
		return makeError(Errc::kInvalidArgument, "view templates: empty mesh");
	// About 128 pixels across the object at a metre or more: enough for an
	// even sample, and perspective close to the test distances.
	constexpr int kSize = 160;
	const double distance = std::max(1000.0, 3.0 * diameter);
	const double f = 128.0 * distance / diameter;
	const CameraIntrinsics K{f, f, (kSize - 1) * 0.5, (kSize - 1) * 0.5, kSize, kSize};
	const float edgeJump = static_cast<float>(0.05 * diameter);

	DepthRenderer renderer(mesh.vertices.size());
	std::vector<float> depth(static_cast<size_t>(kSize) * kSize);
	std::vector<int> interior, any;
	std::vector<Eigen::Vector3f> out;
	out.reserve(static_cast<size_t>(config.viewpoints) * config.pointsPerView);
	for (int v = 0; v < config.viewpoints; ++v) {
		Pose pose;
		pose.R = lookAtRotation(fibonacciDirection(v, config.viewpoints), 0.0);
		pose.t = Eigen::Vector3d(0, 0, distance);
		std::fill(depth.begin(), depth.end(), 0.0f);
		ImageView<float> view(depth.data(), kSize, kSize, kSize);
		auto r = renderer.render(mesh, pose, K, view);
		if (!r)
			return makeError(r.error().code, "view templates: " + std::string(r.error().message));
		interior.clear();
		any.clear();
		for (int y = 1; y + 1 < kSize; ++y)
			for (int x = 1; x + 1 < kSize; ++x) {
				const float z = view.at(x, y);
				if (!(z > 0))
					continue;
				any.push_back(y * kSize + x);
				bool edge = false;
				for (float zn : {view.at(x - 1, y), view.at(x + 1, y), view.at(x, y - 1), view.at(x, y + 1)})
					edge = edge || !(zn > 0) || std::abs(zn - z) > edgeJump;
				if (!edge)
					interior.push_back(y * kSize + x);
			}
		const std::vector<int> &src = interior.size() >= static_cast<size_t>(config.pointsPerView) / 2 ? interior : any;
		if (src.empty())
			return makeError(Errc::kInvalidArgument,
					 "view templates: view " + std::to_string(v) + " shows no surface (degenerate mesh?)");
		// Evenly spaced in raster order over the silhouette: an even spread
		// over the visible surface at this resolution.
		const Eigen::Matrix3d Rt = pose.R.transpose();
		for (int i = 0; i < config.pointsPerView; ++i) {
			const size_t j = std::min(src.size() - 1, static_cast<size_t>(
				(static_cast<double>(i) + 0.5) * src.size() / config.pointsPerView));
			const int x = src[j] % kSize, y = src[j] / kSize;
			const Eigen::Vector3d cam = K.backProject(x, y, view.at(x, y));
			out.push_back((Rt * (cam - pose.t)).cast<float>());
		}
	}
	return out;
}

} // namespace ihf
