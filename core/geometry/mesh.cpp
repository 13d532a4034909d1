// SPDX-License-Identifier: MIT
#include "core/geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

namespace ihf {

Aabb boundingBox(const Mesh &mesh)
{
	Aabb box;
	if (mesh.vertices.empty())
		return box;
	box.min = box.max = mesh.vertices.front();
	for (const Eigen::Vector3f &v : mesh.vertices) {
		box.min = box.min.cwiseMin(v);
		box.max = box.max.cwiseMax(v);
	}
	return box;
}

/*
 * Exact diameter by a pruned all-pairs search. With c the box centre and
 * r_i = |p_i - c|, any pair satisfies |p_i - p_j| <= r_i + r_j, so after
 * sorting by r descending the scan of row i stops at the first j with
 * r_i + r_j below the best distance found so far, and the whole search stops
 * when 2 r_i drops below it. A farthest-point walk seeds a good lower bound.
 * Rows are scanned in float (vectorises); a row whose float maximum comes
 * within rounding of the best is re-evaluated in double, so the result is the
 * double-precision maximum over all pairs.
 */
double meshDiameter(const Mesh &mesh)
{
	const auto &v = mesh.vertices;
	const size_t n = v.size();
	if (n < 2)
		return 0.0;

	auto dist2 = [&v](size_t a, size_t b) { return (v[a].cast<double>() - v[b].cast<double>()).squaredNorm(); };

	// Farthest-point walk: a few hops give (almost always) the diameter.
	double best2 = 0.0;
	size_t a = 0;
	for (int hop = 0; hop < 4; ++hop) {
		size_t far = a;
		double far2 = 0.0;
		for (size_t j = 0; j < n; ++j) {
			double d2 = dist2(a, j);
			if (d2 > far2) {
				far2 = d2;
				far = j;
			}
		}
		if (far2 <= best2)
			break;
		best2 = far2;
		a = far;
	}

	const Aabb box = boundingBox(mesh);
	const Eigen::Vector3d c = box.centre().cast<double>();
	std::vector<uint32_t> order(n);
	std::iota(order.begin(), order.end(), 0u);
	std::vector<double> radius(n);
	for (size_t i = 0; i < n; ++i)
		radius[i] = (v[i].cast<double>() - c).norm();
	std::sort(order.begin(), order.end(), [&radius](uint32_t x, uint32_t y) { return radius[x] > radius[y]; });

	// Sorted structure-of-arrays copy for the vectorised inner loop.
	std::vector<float> xs(n), ys(n), zs(n);
	std::vector<double> rs(n);
	for (size_t i = 0; i < n; ++i) {
		const Eigen::Vector3f &p = v[order[i]];
		xs[i] = p.x();
		ys[i] = p.y();
		zs[i] = p.z();
		rs[i] = radius[order[i]];
	}

	// Slack for float rounding in the row scan and in the radius bound.
	const double kRel = 1e-5;
	double best = std::sqrt(best2);
	for (size_t i = 0; i + 1 < n; ++i) {
		if (2.0 * rs[i] < best * (1.0 - kRel))
			break;
		// Rows j with rs[i] + rs[j] below best cannot beat it.
		const double need = best * (1.0 - kRel) - rs[i];
		size_t jEnd = std::partition_point(rs.begin() + i + 1, rs.end(),
						   [need](double r) { return r >= need; }) - rs.begin();
		const float px = xs[i], py = ys[i], pz = zs[i];
		float rowMax = 0.0f;
		for (size_t j = i + 1; j < jEnd; ++j) {
			float dx = xs[j] - px, dy = ys[j] - py, dz = zs[j] - pz;
			rowMax = std::max(rowMax, dx * dx + dy * dy + dz * dz);
		}
		if (static_cast<double>(rowMax) < best2 * (1.0 - kRel))
			continue;
		// Close to or above the best: settle it exactly.
		for (size_t j = i + 1; j < jEnd; ++j) {
			double d2 = dist2(order[i], order[j]);
			if (d2 > best2) {
				best2 = d2;
				best = std::sqrt(best2);
			}
		}
	}
	return best;
}

size_t countDegenerateFaces(const Mesh &mesh)
{
	size_t count = 0;
	const size_t n = mesh.vertices.size();
	for (const auto &f : mesh.faces) {
		if (f[0] >= n || f[1] >= n || f[2] >= n || f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
			++count;
			continue;
		}
		const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>();
		const Eigen::Vector3d b = mesh.vertices[f[1]].cast<double>();
		const Eigen::Vector3d c = mesh.vertices[f[2]].cast<double>();
		// Area relative to the longest edge squared: 1e-9 is collinear up to
		// float rounding of the coordinates.
		const double twiceArea = (b - a).cross(c - a).norm();
		const double edge2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
		if (twiceArea <= 1e-9 * edge2)
			++count;
	}
	return count;
}

} // namespace ihf
