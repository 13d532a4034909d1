// SPDX-License-Identifier: MIT
#include "core/geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

namespace ihf {

namespace {

// A face with a repeated index covers nothing.
bool repeatsIndex(const std::array<uint32_t, 3> &f)
{
	return f[0] == f[1] || f[1] == f[2] || f[2] == f[0];
}

// Six times the signed volume of the tetrahedron from the origin to face f.
double originVolume6(const Mesh &mesh, const std::array<uint32_t, 3> &f)
{
	return mesh.vertices[f[0]].cast<double>().dot(
		mesh.vertices[f[1]].cast<double>().cross(mesh.vertices[f[2]].cast<double>()));
}

} // namespace

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

bool isDegenerateFace(const Mesh &mesh, const std::array<uint32_t, 3> &f)
{
	const size_t n = mesh.vertices.size();
	if (f[0] >= n || f[1] >= n || f[2] >= n || repeatsIndex(f))
		return true;
	const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>();
	const Eigen::Vector3d b = mesh.vertices[f[1]].cast<double>();
	const Eigen::Vector3d c = mesh.vertices[f[2]].cast<double>();
	// Area relative to the longest edge squared: 1e-9 is collinear up to
	// float rounding of the coordinates.
	const double twiceArea = (b - a).cross(c - a).norm();
	const double edge2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
	return twiceArea <= 1e-9 * edge2;
}

size_t countDegenerateFaces(const Mesh &mesh)
{
	size_t count = 0;
	for (const auto &f : mesh.faces) {
		if (isDegenerateFace(mesh, f))
			++count;
	}
	return count;
}

/*
 * Closed and oriented: every edge is run as often one way as the other by
 * the faces that share it (two faces for a manifold edge; a pinch where
 * two sheets touch has four); outward: the signed volume, summed from the
 * origin's tetrahedra, is positive. Faces with a repeated index cover
 * nothing and are left out.
 */
bool isClosedOutward(const Mesh &mesh)
{
	std::vector<uint64_t> edges;
	edges.reserve(3 * mesh.faces.size());
	double volume = 0.0;
	const size_t nv = mesh.vertices.size();
	for (const auto &f : mesh.faces) {
		if (f[0] >= nv || f[1] >= nv || f[2] >= nv)
			return false;
		if (repeatsIndex(f))
			continue;
		for (int i = 0; i < 3; ++i)
			edges.push_back(uint64_t{f[i]} << 32 | f[(i + 1) % 3]);
		volume += originVolume6(mesh, f);
	}
	if (edges.empty())
		return false;
	std::sort(edges.begin(), edges.end());
	for (size_t i = 0; i < edges.size();) {
		const uint64_t e = edges[i];
		size_t j = i;
		while (j < edges.size() && edges[j] == e)
			++j;
		const uint64_t reverse = (e << 32) | (e >> 32);
		const auto back = std::equal_range(edges.begin(), edges.end(), reverse);
		if (static_cast<size_t>(back.second - back.first) != j - i)
			return false; // an open edge, or faces running it the same way
		i = j;
	}
	return volume > 0.0;
}

/*
 * Each edge must join an even number of faces (closed); two faces that run
 * their shared edge the same way disagree in winding, so one of them turns
 * (an edge of four faces or more, a pinch, ties none). A breadth-first
 * walk over each connected shell fixes every face's winding relative to
 * its first face (a conflict means the shell cannot be oriented); a shell
 * whose signed volume is then negative turns whole.
 */
bool orientClosedOutward(Mesh &mesh)
{
	const size_t nv = mesh.vertices.size(), nf = mesh.faces.size();
	struct EdgeUse {
		uint64_t key; // lower vertex << 32 | upper vertex
		uint32_t face;
		bool forward; // the face runs it lower -> upper
	};
	std::vector<EdgeUse> uses;
	uses.reserve(3 * nf);
	for (size_t fi = 0; fi < nf; ++fi) {
		const auto &f = mesh.faces[fi];
		if (f[0] >= nv || f[1] >= nv || f[2] >= nv)
			return false;
		if (repeatsIndex(f))
			continue;
		for (int i = 0; i < 3; ++i) {
			const uint32_t a = f[i], b = f[(i + 1) % 3];
			uses.push_back({uint64_t{std::min(a, b)} << 32 | std::max(a, b), static_cast<uint32_t>(fi), a < b});
		}
	}
	if (uses.empty())
		return false;
	std::sort(uses.begin(), uses.end(), [](const EdgeUse &x, const EdgeUse &y) { return x.key < y.key; });
	// Per face its three neighbours and whether each must turn relative to it.
	constexpr uint32_t kNone = UINT32_MAX;
	std::vector<std::array<uint32_t, 3>> next(nf, {kNone, kNone, kNone});
	std::vector<std::array<bool, 3>> turn(nf);
	std::vector<uint8_t> filled(nf, 0);
	for (size_t i = 0; i < uses.size();) {
		size_t j = i;
		while (j < uses.size() && uses[j].key == uses[i].key)
			++j;
		if ((j - i) % 2 != 0)
			return false; // an open edge
		if (j - i == 2) {
			// A manifold edge ties its two faces' windings; a pinch (four
			// faces or more) ties none, the check at the end judges it.
			const EdgeUse &x = uses[i], &y = uses[i + 1];
			if (x.face == y.face)
				return false;
			const bool disagree = x.forward == y.forward;
			next[x.face][filled[x.face]] = y.face;
			turn[x.face][filled[x.face]++] = disagree;
			next[y.face][filled[y.face]] = x.face;
			turn[y.face][filled[y.face]++] = disagree;
		}
		i = j;
	}
	std::vector<int8_t> flip(nf, -1); // -1: not reached yet
	std::vector<uint32_t> queue;
	queue.reserve(nf);
	for (size_t seed = 0; seed < nf; ++seed) {
		if (flip[seed] >= 0 || repeatsIndex(mesh.faces[seed]))
			continue;
		// One shell: orient it from the seed, then turn it outwards.
		queue.clear();
		queue.push_back(static_cast<uint32_t>(seed));
		flip[seed] = 0;
		for (size_t q = 0; q < queue.size(); ++q) {
			const uint32_t f = queue[q];
			for (int k = 0; k < filled[f]; ++k) {
				const uint32_t g = next[f][k];
				const int8_t want = static_cast<int8_t>(flip[f] ^ turn[f][k]);
				if (flip[g] < 0) {
					flip[g] = want;
					queue.push_back(g);
				} else if (flip[g] != want) {
					return false; // not orientable
				}
			}
		}
		double volume = 0.0;
		for (const uint32_t f : queue) {
			if (flip[f])
				std::swap(mesh.faces[f][1], mesh.faces[f][2]);
			volume += originVolume6(mesh, mesh.faces[f]);
		}
		if (volume < 0.0)
			for (const uint32_t f : queue)
				std::swap(mesh.faces[f][1], mesh.faces[f][2]);
	}
	return isClosedOutward(mesh);
}

} // namespace ihf
