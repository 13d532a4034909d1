// SPDX-License-Identifier: MIT
#include "core/synth/primitive_mesh.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace ihf {

namespace {

uint32_t addVertex(Mesh &m, const Eigen::Vector3f &p, const Eigen::Vector3f &n)
{
	m.vertices.push_back(p);
	m.normals.push_back(n);
	return static_cast<uint32_t>(m.vertices.size() - 1);
}

// Flat quad a-b-c-d (counter-clockwise seen from outside) with its own
// vertices so the normals stay sharp at the box edges.
void addFace(Mesh &m, const Eigen::Vector3f &a, const Eigen::Vector3f &b,
	     const Eigen::Vector3f &c, const Eigen::Vector3f &d)
{
	const Eigen::Vector3f n = (b - a).cross(c - a).normalized();
	const uint32_t i0 = addVertex(m, a, n), i1 = addVertex(m, b, n);
	const uint32_t i2 = addVertex(m, c, n), i3 = addVertex(m, d, n);
	m.faces.push_back({i0, i1, i2});
	m.faces.push_back({i0, i2, i3});
}

} // namespace

Mesh makeBox(double sx, double sy, double sz)
{
	Mesh m;
	const float x = static_cast<float>(sx / 2), y = static_cast<float>(sy / 2);
	const float z = static_cast<float>(sz);
	using V = Eigen::Vector3f;
	addFace(m, V(-x, -y, 0), V(-x, y, 0), V(x, y, 0), V(x, -y, 0)); // bottom
	addFace(m, V(-x, -y, z), V(x, -y, z), V(x, y, z), V(-x, y, z)); // top
	addFace(m, V(-x, -y, 0), V(x, -y, 0), V(x, -y, z), V(-x, -y, z));
	addFace(m, V(x, -y, 0), V(x, y, 0), V(x, y, z), V(x, -y, z));
	addFace(m, V(x, y, 0), V(-x, y, 0), V(-x, y, z), V(x, y, z));
	addFace(m, V(-x, y, 0), V(-x, -y, 0), V(-x, -y, z), V(-x, y, z));
	return m;
}

Mesh makeCylinder(double radius, double height, int segments)
{
	Mesh m;
	const float r = static_cast<float>(radius), h = static_cast<float>(height);
	const uint32_t bottomCentre = addVertex(m, {0, 0, 0}, {0, 0, -1});
	const uint32_t topCentre = addVertex(m, {0, 0, h}, {0, 0, 1});
	const uint32_t first = static_cast<uint32_t>(m.vertices.size());
	for (int i = 0; i < segments; ++i) {
		const double a = 2.0 * std::numbers::pi * i / segments;
		const float c = static_cast<float>(std::cos(a)), s = static_cast<float>(std::sin(a));
		addVertex(m, {r * c, r * s, 0}, {c, s, 0}); // side bottom
		addVertex(m, {r * c, r * s, h}, {c, s, 0}); // side top
		addVertex(m, {r * c, r * s, 0}, {0, 0, -1}); // cap bottom
		addVertex(m, {r * c, r * s, h}, {0, 0, 1}); // cap top
	}
	for (int i = 0; i < segments; ++i) {
		const uint32_t a = first + 4 * i, b = first + 4 * ((i + 1) % segments);
		m.faces.push_back({a, b, b + 1});
		m.faces.push_back({a, b + 1, a + 1});
		m.faces.push_back({bottomCentre, b + 2, a + 2});
		m.faces.push_back({topCentre, a + 3, b + 3});
	}
	return m;
}

Mesh makeLyingCylinder(double radius, double length, int segments)
{
	// Upright cylinder centred on its axis, rotated so the axis runs along x.
	Mesh m = makeCylinder(radius, length, segments);
	const float half = static_cast<float>(length / 2), r = static_cast<float>(radius);
	for (size_t i = 0; i < m.vertices.size(); ++i) {
		const Eigen::Vector3f p = m.vertices[i], n = m.normals[i];
		m.vertices[i] = {p.z() - half, p.y(), p.x() + r};
		m.normals[i] = {n.z(), n.y(), n.x()};
	}
	// The x/z swap mirrors the mesh: flip the winding to keep normals outward.
	for (auto &f : m.faces)
		std::swap(f[1], f[2]);
	return m;
}

Mesh makeSphere(double radius, int rings, int segments)
{
	Mesh m;
	const float r = static_cast<float>(radius);
	for (int i = 0; i <= rings; ++i) {
		const double theta = std::numbers::pi * i / rings;
		for (int j = 0; j <= segments; ++j) {
			const double phi = 2.0 * std::numbers::pi * j / segments;
			const Eigen::Vector3f n(static_cast<float>(std::sin(theta) * std::cos(phi)),
						static_cast<float>(std::sin(theta) * std::sin(phi)),
						static_cast<float>(-std::cos(theta)));
			addVertex(m, r * n + Eigen::Vector3f(0, 0, r), n);
		}
	}
	const uint32_t row = static_cast<uint32_t>(segments + 1);
	for (int i = 0; i < rings; ++i) {
		for (int j = 0; j < segments; ++j) {
			const uint32_t a = i * row + j, b = a + 1, c = a + row, d = c + 1;
			if (i > 0)
				m.faces.push_back({a, b, d});
			if (i < rings - 1)
				m.faces.push_back({a, d, c});
		}
	}
	return m;
}

Mesh makeQuad(double sx, double sy)
{
	Mesh m;
	const float x = static_cast<float>(sx / 2), y = static_cast<float>(sy / 2);
	using V = Eigen::Vector3f;
	addFace(m, V(-x, -y, 0), V(x, -y, 0), V(x, y, 0), V(-x, y, 0));
	return m;
}

} // namespace ihf
