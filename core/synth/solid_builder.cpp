// SPDX-License-Identifier: MIT
#include "core/synth/solid_builder.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace ihf {

namespace {

// Six times the signed volume the faces enclose.
double signedVolume6(const Mesh &m)
{
	double v = 0;
	for (const auto &f : m.faces)
		v += static_cast<double>(m.vertices[f[0]].dot(m.vertices[f[1]].cross(m.vertices[f[2]])));
	return v;
}

// A closed shell built with one winding throughout turned outwards.
void windOutwards(Mesh &m)
{
	if (signedVolume6(m) < 0)
		for (auto &f : m.faces)
			std::swap(f[1], f[2]);
}

uint32_t add(Mesh &m, const Eigen::Vector3d &p)
{
	m.vertices.push_back(p.cast<float>());
	return static_cast<uint32_t>(m.vertices.size() - 1);
}

// Faces between two rings of n vertices starting at a and b, or between a
// ring and a single pole vertex (n == 1 on one side).
void joinRings(Mesh &m, uint32_t a, int na, uint32_t b, int nb, int n)
{
	for (int j = 0; j < n; ++j) {
		const uint32_t j1 = static_cast<uint32_t>((j + 1) % n), j0 = static_cast<uint32_t>(j);
		const uint32_t a0 = na == 1 ? a : a + j0, a1 = na == 1 ? a : a + j1;
		const uint32_t b0 = nb == 1 ? b : b + j0, b1 = nb == 1 ? b : b + j1;
		if (na != 1)
			m.faces.push_back({a0, a1, b1});
		if (nb != 1)
			m.faces.push_back({a0, b1, b0});
	}
}

} // namespace

Mesh makeLathe(std::span<const Eigen::Vector2d> profile, int segments)
{
	Mesh m;
	std::vector<std::pair<uint32_t, int>> rings; // first vertex, count
	for (const Eigen::Vector2d &p : profile) {
		if (p.x() <= 0) {
			rings.emplace_back(add(m, {0, 0, p.y()}), 1);
			continue;
		}
		const uint32_t first = static_cast<uint32_t>(m.vertices.size());
		for (int j = 0; j < segments; ++j) {
			const double a = 2.0 * std::numbers::pi * j / segments;
			add(m, {p.x() * std::cos(a), p.x() * std::sin(a), p.y()});
		}
		rings.emplace_back(first, segments);
	}
	for (size_t i = 0; i + 1 < rings.size(); ++i)
		joinRings(m, rings[i].first, rings[i].second, rings[i + 1].first, rings[i + 1].second, segments);
	windOutwards(m);
	return m;
}

Mesh makeTube(std::span<const Eigen::Vector3d> path, double radius, const Eigen::Vector3d &up, int segments)
{
	Mesh m;
	const size_t n = path.size();
	const uint32_t startCap = add(m, path[0]);
	std::vector<uint32_t> rings;
	for (size_t i = 0; i < n; ++i) {
		const Eigen::Vector3d tangent =
			(path[std::min(i + 1, n - 1)] - path[i == 0 ? 0 : i - 1]).normalized();
		const Eigen::Vector3d side = up.cross(tangent).normalized();
		const Eigen::Vector3d normal = tangent.cross(side);
		rings.push_back(static_cast<uint32_t>(m.vertices.size()));
		for (int j = 0; j < segments; ++j) {
			const double a = 2.0 * std::numbers::pi * j / segments;
			add(m, path[i] + radius * (std::cos(a) * side + std::sin(a) * normal));
		}
	}
	const uint32_t endCap = add(m, path[n - 1]);
	joinRings(m, startCap, 1, rings[0], segments, segments);
	for (size_t i = 0; i + 1 < n; ++i)
		joinRings(m, rings[i], segments, rings[i + 1], segments, segments);
	joinRings(m, rings[n - 1], segments, endCap, 1, segments);
	windOutwards(m);
	return m;
}

Mesh makeSolidBox(const Eigen::Vector3d &lo, const Eigen::Vector3d &hi)
{
	Mesh m;
	for (int i = 0; i < 8; ++i)
		add(m, {(i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z()});
	// Each side as two triangles, counter-clockwise seen from outside.
	const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
				      {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
	for (const auto &q : quads) {
		m.faces.push_back({q[0], q[1], q[2]});
		m.faces.push_back({q[0], q[2], q[3]});
	}
	windOutwards(m);
	return m;
}

void transformMesh(Mesh &mesh, const Eigen::Matrix3d &R, const Eigen::Vector3d &t)
{
	for (Eigen::Vector3f &v : mesh.vertices)
		v = (R * v.cast<double>() + t).cast<float>();
	for (Eigen::Vector3f &n : mesh.normals)
		n = (R * n.cast<double>()).cast<float>();
	if (R.determinant() < 0)
		for (auto &f : mesh.faces)
			std::swap(f[1], f[2]);
}

void appendMesh(Mesh &mesh, const Mesh &part)
{
	const uint32_t base = static_cast<uint32_t>(mesh.vertices.size());
	mesh.vertices.insert(mesh.vertices.end(), part.vertices.begin(), part.vertices.end());
	for (const auto &f : part.faces)
		mesh.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
}

} // namespace ihf
