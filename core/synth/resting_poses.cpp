// SPDX-License-Identifier: MIT
#include "core/synth/resting_poses.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include <Eigen/Geometry>

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

// Evenly spread unit vectors (Fibonacci lattice): equal area per point, so
// counting points measures solid angle.
std::vector<Eigen::Vector3d> fibonacciSphere(int n)
{
	std::vector<Eigen::Vector3d> dirs(n);
	const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
	for (int i = 0; i < n; ++i) {
		const double z = 1.0 - (2.0 * i + 1.0) / n;
		const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
		dirs[i] = {r * std::cos(golden * i), r * std::sin(golden * i), z};
	}
	return dirs;
}

struct Support {
	std::vector<Eigen::Vector3d> points; // hull vertex candidates
	Eigen::Vector3d com;

	double height(const Eigen::Vector3d &d) const
	{
		double best = -std::numeric_limits<double>::max();
		for (const auto &p : points)
			best = std::max(best, d.dot(p));
		return best - d.dot(com);
	}
};

// Pattern search on the sphere from d: the minimum of H is a kink (a hull
// face normal), so gradients are useless; halve the step until ~0.01 deg.
Eigen::Vector3d refineMinimum(const Support &s, Eigen::Vector3d d, double step)
{
	double h = s.height(d);
	while (step > 2e-4) {
		Eigen::Vector3d t1 = d.unitOrthogonal();
		Eigen::Vector3d t2 = d.cross(t1);
		bool improved = false;
		for (int k = 0; k < 8; ++k) {
			const double a = k * std::numbers::pi / 4.0;
			const Eigen::Vector3d c =
				(d + step * (std::cos(a) * t1 + std::sin(a) * t2)).normalized();
			const double hc = s.height(c);
			if (hc < h - 1e-9) {
				h = hc;
				d = c;
				improved = true;
				break;
			}
		}
		if (!improved)
			step *= 0.5;
	}
	return d;
}

} // namespace

std::vector<RestingPose> computeRestingPoses(const Mesh &mesh, int directions,
					     double minProbability)
{
	std::vector<RestingPose> poses;
	if (mesh.vertices.empty())
		return poses;

	const std::vector<Eigen::Vector3d> dirs = fibonacciSphere(directions);
	Support support;
	support.com = centreOfMass(mesh);

	// The extreme vertex of each sampled direction: a subset of the convex
	// hull vertices that makes the support function cheap to evaluate.
	std::set<uint32_t> extremes;
	for (const auto &d : dirs) {
		uint32_t best = 0;
		double bestDot = -std::numeric_limits<double>::max();
		for (uint32_t i = 0; i < mesh.vertices.size(); ++i) {
			const double v = d.dot(mesh.vertices[i].cast<double>());
			if (v > bestDot) {
				bestDot = v;
				best = i;
			}
		}
		extremes.insert(best);
	}
	for (uint32_t i : extremes)
		support.points.push_back(mesh.vertices[i].cast<double>());

	std::vector<double> height(dirs.size());
	for (size_t i = 0; i < dirs.size(); ++i)
		height[i] = support.height(dirs[i]);

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

	// Steepest descent from every lattice point; count basin sizes.
	std::vector<int> sink(dirs.size(), -1);
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
		sink[i] = cur;
	}
	std::vector<int> basin(dirs.size(), 0);
	for (int s : sink)
		++basin[s];

	// Refine each lattice minimum and merge those that reach the same face.
	struct Candidate {
		Eigen::Vector3d d;
		double share;
	};
	std::vector<Candidate> found;
	const double spacing = std::sqrt(4.0 * std::numbers::pi / directions);
	for (size_t i = 0; i < dirs.size(); ++i) {
		if (basin[i] == 0)
			continue;
		const Eigen::Vector3d d = refineMinimum(support, dirs[i], spacing);
		const double share = static_cast<double>(basin[i]) / directions;
		bool merged = false;
		for (auto &c : found) {
			if (c.d.dot(d) > std::cos(3.0 * std::numbers::pi / 180.0)) {
				c.share += share;
				merged = true;
				break;
			}
		}
		if (!merged)
			found.push_back({d, share});
	}

	double total = 0;
	for (const auto &c : found)
		if (c.share >= minProbability)
			total += c.share;
	for (const auto &c : found) {
		if (c.share < minProbability || total <= 0)
			continue;
		RestingPose pose;
		// Rotate the "down" direction d onto -z.
		pose.R = Eigen::Quaterniond::FromTwoVectors(c.d, Eigen::Vector3d(0, 0, -1))
				 .toRotationMatrix();
		pose.probability = c.share / total;
		rotatedBounds(mesh, pose.R, pose.min, pose.max);
		poses.push_back(pose);
	}
	std::stable_sort(poses.begin(), poses.end(), [](const RestingPose &a, const RestingPose &b) {
		return a.probability > b.probability;
	});
	return poses;
}

} // namespace ihf
