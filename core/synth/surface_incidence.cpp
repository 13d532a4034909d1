// SPDX-License-Identifier: MIT
#include "core/synth/surface_incidence.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace ihf {

IncidenceMap computeIncidence(ImageView<const float> depth, const CameraIntrinsics &K,
			      double jumpMm, double jumpRel)
{
	const int W = depth.width, H = depth.height;
	IncidenceMap m;
	m.width = W;
	m.height = H;
	const float unknown = static_cast<float>(std::numbers::pi / 2);
	m.angle.assign(static_cast<size_t>(W) * H, unknown);
	m.edge.assign(static_cast<size_t>(W) * H, 0);

	auto point = [&](int x, int y) { return K.backProject(x, y, depth.at(x, y)); };
	for (int y = 0; y < H; ++y) {
		for (int x = 0; x < W; ++x) {
			const float z = depth.at(x, y);
			if (z <= 0.0f)
				continue;
			const double jump = std::max(jumpMm, jumpRel * z);
			// Best one-sided neighbour on each axis; an empty or far
			// neighbour marks the pixel as an edge.
			auto pick = [&](int dx, int dy, Eigen::Vector3d &d) {
				double best = jump;
				bool found = false, edge = false;
				for (int s : {-1, 1}) {
					const int nx = x + s * dx, ny = y + s * dy;
					if (nx < 0 || ny < 0 || nx >= W || ny >= H)
						continue;
					const float zn = depth.at(nx, ny);
					const double step = zn > 0.0f ? std::abs(zn - z) : 1e30;
					if (step > jump)
						edge = true;
					if (step <= best) {
						best = step;
						d = s * (point(nx, ny) - point(x, y));
						found = true;
					}
				}
				return std::pair{found, edge};
			};
			Eigen::Vector3d dx = Eigen::Vector3d::Zero(), dy = Eigen::Vector3d::Zero();
			const auto [fx, ex] = pick(1, 0, dx);
			const auto [fy, ey] = pick(0, 1, dy);
			m.edge[static_cast<size_t>(y) * W + x] = (ex || ey) ? 1 : 0;
			if (!fx || !fy)
				continue;
			const Eigen::Vector3d n = dx.cross(dy);
			const Eigen::Vector3d ray = point(x, y);
			const double c = std::abs(n.dot(ray)) / std::max(n.norm() * ray.norm(), 1e-12);
			m.angle[static_cast<size_t>(y) * W + x] =
				static_cast<float>(std::acos(std::min(c, 1.0)));
		}
	}
	return m;
}

} // namespace ihf
