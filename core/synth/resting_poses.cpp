// SPDX-License-Identifier: MIT
#include "core/synth/resting_poses.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

#include "core/geometry/rotation.h"
#include "core/synth/convex_hull.h"

namespace ihf {

Eigen::Vector3d centreOfMass(const Mesh &mesh)
{
	Eigen::Vector3d sum = Eigen::Vector3d::Zero();
	double volume = 0;
	for (const auto &f : mesh.faces) {
		const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>();
		const Eigen::Vector3d b = mesh.vertices[f[1]].cast<double>();
		const Eigen::Vector3d c = mesh.vertices[f[2]].cast<double>();
		// Signed volume of the tetrahedron (origin, a, b, c).
		const double v = a.dot(b.cross(c)) / 6.0;
		volume += v;
		sum += v * (a + b + c) / 4.0;
	}
	Eigen::Vector3d mean = Eigen::Vector3d::Zero();
	for (const auto &p : mesh.vertices)
		mean += p.cast<double>();
	if (!mesh.vertices.empty())
		mean /= static_cast<double>(mesh.vertices.size());
	const Aabb box = boundingBox(mesh);
	const double scale = box.size().cast<double>().prod();
	if (std::abs(volume) < 1e-6 * std::max(scale, 1e-12))
		return mean;
	return sum / volume;
}

void rotatedBounds(const Mesh &mesh, const Eigen::Matrix3d &R, Eigen::Vector3d &min,
		   Eigen::Vector3d &max)
{
	min = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
	max = -min;
	for (const auto &p : mesh.vertices) {
		const Eigen::Vector3d q = R * p.cast<double>();
		min = min.cwiseMin(q);
		max = max.cwiseMax(q);
	}
}

namespace {

// Whether q lies inside the convex hull of the (coplanar) points, in the
// plane with normal n, with at least margin to spare.
bool insideFacet(const std::vector<Eigen::Vector3d> &pts, const Eigen::Vector3d &n,
		 const Eigen::Vector3d &q, double margin)
{
	const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
	std::vector<Eigen::Vector2d> p2;
	for (const auto &p : pts)
		p2.push_back({p.dot(u), p.dot(v)});
	// Andrew's monotone chain: the facet outline counter-clockwise.
	std::sort(p2.begin(), p2.end(), [](const auto &a, const auto &b) {
		return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
	});
	auto cross = [](const Eigen::Vector2d &o, const Eigen::Vector2d &a, const Eigen::Vector2d &b) {
		return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
	};
	std::vector<Eigen::Vector2d> hull(2 * p2.size());
	size_t k = 0;
	for (size_t i = 0; i < p2.size(); ++i) {
		while (k >= 2 && cross(hull[k - 2], hull[k - 1], p2[i]) <= 0)
			--k;
		hull[k++] = p2[i];
	}
	for (size_t i = p2.size() - 1, t = k + 1; i-- > 0;) {
		while (k >= t && cross(hull[k - 2], hull[k - 1], p2[i]) <= 0)
			--k;
		hull[k++] = p2[i];
	}
	if (k < 4)
		return false; // degenerate outline
	hull.resize(k - 1);
	const Eigen::Vector2d q2(q.dot(u), q.dot(v));
	for (size_t i = 0; i < hull.size(); ++i) {
		const Eigen::Vector2d &a = hull[i], &b = hull[(i + 1) % hull.size()];
		const double len = (b - a).norm();
		if (len <= 0 || cross(a, b, q2) / len < margin)
			return false;
	}
	return true;
}

} // namespace

Expected<std::vector<RestingPose>> computeRestingPoses(const Mesh &mesh, int directions,
						       double minProbability)
{
	std::vector<Eigen::Vector3d> points;
	points.reserve(mesh.vertices.size());
	for (const auto &p : mesh.vertices)
		points.push_back(p.cast<double>());
	auto hull = convexHull(points);
	if (!hull)
		return hull.error();
	const Eigen::Vector3d com = centreOfMass(mesh);

	// Stable facets: the centre of mass projects inside. A scanned flat
	// base is many nearly coplanar facets; the one under the centre of
	// mass is the stable one.
	std::vector<const HullFacet *> stable;
	for (const HullFacet &f : *hull)
		if (insideFacet(f.vertices, f.normal, com, 0.0))
			stable.push_back(&f);
	if (stable.empty())
		return makeError(Errc::kCorrupt, "resting poses: no stable hull facet");

	// H on the lattice, over the hull vertices only.
	std::vector<Eigen::Vector3d> hullPoints;
	for (const HullFacet &f : *hull)
		hullPoints.insert(hullPoints.end(), f.vertices.begin(), f.vertices.end());
	const std::vector<Eigen::Vector3d> dirs = fibonacciSphere(directions);
	std::vector<double> height(dirs.size());
	for (size_t i = 0; i < dirs.size(); ++i) {
		double best = -std::numeric_limits<double>::max();
		for (const auto &p : hullPoints)
			best = std::max(best, dirs[i].dot(p));
		height[i] = best - dirs[i].dot(com);
	}

	// Neighbours on the lattice: the k nearest directions.
	constexpr int kNeighbours = 8;
	std::vector<std::array<int, kNeighbours>> nbr(dirs.size());
	for (size_t i = 0; i < dirs.size(); ++i) {
		std::array<std::pair<double, int>, kNeighbours> best;
		best.fill({-2.0, -1});
		for (size_t j = 0; j < dirs.size(); ++j) {
			if (j == i)
				continue;
			const double c = dirs[i].dot(dirs[j]);
			if (c > best.back().first) {
				best.back() = {c, static_cast<int>(j)};
				std::sort(best.begin(), best.end(),
					  [](const auto &a, const auto &b) { return a.first > b.first; });
			}
		}
		for (int k = 0; k < kNeighbours; ++k)
			nbr[i][k] = best[k].second;
	}

	// Steepest descent from every lattice point; the basin of a lattice
	// minimum goes to the stable facet whose normal is nearest.
	std::vector<double> share(stable.size(), 0.0);
	for (size_t i = 0; i < dirs.size(); ++i) {
		int cur = static_cast<int>(i);
		for (;;) {
			int next = cur;
			for (int j : nbr[cur])
				if (height[j] < height[next])
					next = j;
			if (next == cur)
				break;
			cur = next;
		}
		size_t bestFacet = 0;
		for (size_t f = 1; f < stable.size(); ++f)
			if (stable[f]->normal.dot(dirs[cur]) > stable[bestFacet]->normal.dot(dirs[cur]))
				bestFacet = f;
		share[bestFacet] += 1.0 / directions;
	}

	// Facets within 2 degrees are one resting pose for the eye: pool their
	// drops on the one that caught most.
	for (size_t a = 0; a < stable.size(); ++a) {
		for (size_t b = 0; b < stable.size(); ++b) {
			if (a == b || share[a] <= 0 || share[b] <= 0 || share[b] > share[a])
				continue;
			if (share[b] == share[a] && b < a)
				continue;
			if (stable[a]->normal.dot(stable[b]->normal) > std::cos(2.0 * std::numbers::pi / 180)) {
				share[a] += share[b];
				share[b] = 0;
			}
		}
	}
	double total = 0;
	for (double s : share)
		if (s >= minProbability)
			total += s;
	std::vector<RestingPose> poses;
	for (size_t f = 0; f < stable.size(); ++f) {
		if (share[f] < minProbability || share[f] <= 0 || total <= 0)
			continue;
		RestingPose pose;
		// Rotate the facet's outward normal onto -z (the table below).
		pose.R = rotationBetween(stable[f]->normal, Eigen::Vector3d(0, 0, -1));
		pose.probability = share[f] / total;
		rotatedBounds(mesh, pose.R, pose.min, pose.max);
		poses.push_back(pose);
	}
	std::stable_sort(poses.begin(), poses.end(), [](const RestingPose &a, const RestingPose &b) {
		return a.probability > b.probability;
	});
	return poses;
}

} // namespace ihf
