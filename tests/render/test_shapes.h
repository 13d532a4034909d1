// SPDX-License-Identifier: MIT
#pragma once

// Analytic test meshes for the renderer.

#include <cmath>
#include <map>
#include <utility>

#include "core/geometry/mesh.h"

namespace ihf::test {

// Icosphere of the given radius centred at the origin, all vertices exactly
// on the sphere (up to float rounding): 20 * 4^levels faces.
inline Mesh icosphere(float radius, int levels)
{
	const double t = (1.0 + std::sqrt(5.0)) / 2.0;
	std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
					  {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
	for (auto &p : v)
		p.normalize();
	std::vector<std::array<uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
						  {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
						  {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
						  {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
	for (int l = 0; l < levels; ++l) {
		std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
		auto midpoint = [&](uint32_t a, uint32_t b) {
			auto key = std::minmax(a, b);
			auto it = mid.find(key);
			if (it != mid.end())
				return it->second;
			v.push_back((v[a] + v[b]).normalized());
			uint32_t idx = static_cast<uint32_t>(v.size() - 1);
			mid[key] = idx;
			return idx;
		};
		std::vector<std::array<uint32_t, 3>> next;
		for (const auto &tri : f) {
			uint32_t a = midpoint(tri[0], tri[1]);
			uint32_t b = midpoint(tri[1], tri[2]);
			uint32_t c = midpoint(tri[2], tri[0]);
			next.push_back({tri[0], a, c});
			next.push_back({tri[1], b, a});
			next.push_back({tri[2], c, b});
			next.push_back({a, b, c});
		}
		f = std::move(next);
	}
	Mesh m;
	for (const auto &p : v) {
		m.vertices.push_back((p * radius).cast<float>());
		m.normals.push_back(p.cast<float>());
	}
	m.faces = std::move(f);
	return m;
}

// Quad with corners a, b, c, d (in order) as two triangles.
inline Mesh quad(const Eigen::Vector3f &a, const Eigen::Vector3f &b, const Eigen::Vector3f &c,
		 const Eigen::Vector3f &d)
{
	Mesh m;
	m.vertices = {a, b, c, d};
	m.faces = {{0, 1, 2}, {0, 2, 3}};
	return m;
}

} // namespace ihf::test
