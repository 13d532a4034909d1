// SPDX-License-Identifier: MIT
#pragma once

// Uniform cubic B-spline blending functions and the control lattice over the
// unit cube (Eq. 5-6). The paper prints b0 = (1 - u^3)/6; the correct blending
// function is (1 - u)^3 / 6, used here, so that the four sum to one.
//
// A lattice of N nodes per axis spans N - 3 cells of width delta = 1/(N - 3)
// over [0, 1]. A point in cell i (0 <= i <= N - 4) is controlled by nodes
// i .. i + 3; node j sits at (j - 1) * delta, so nodes cover [-delta, 1 + delta].

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

namespace ihf {

inline void cubicBlend(float u, float b[4])
{
	const float u2 = u * u;
	const float u3 = u2 * u;
	const float v = 1.0f - u;
	b[0] = v * v * v / 6.0f;
	b[1] = (3.0f * u3 - 6.0f * u2 + 4.0f) / 6.0f;
	b[2] = (-3.0f * u3 + 3.0f * u2 + 3.0f * u + 1.0f) / 6.0f;
	b[3] = u3 / 6.0f;
}

// Derivatives of the blending functions with respect to u.
inline void cubicBlendDerivative(float u, float d[4])
{
	const float u2 = u * u;
	const float v = 1.0f - u;
	d[0] = -0.5f * v * v;
	d[1] = 1.5f * u2 - 2.0f * u;
	d[2] = -1.5f * u2 + u + 0.5f;
	d[3] = 0.5f * u2;
}

struct Lattice {
	int n = 0; // nodes per axis

	Lattice() = default;
	explicit Lattice(int nodes) : n(nodes) {}

	bool valid() const { return n >= 4; }
	int cells() const { return n - 3; }
	float delta() const { return 1.0f / static_cast<float>(n - 3); }
	int64_t nodeCount() const { return static_cast<int64_t>(n) * n * n; }

	// Cell index (clamped to the lattice) and local coordinate u of x along
	// one axis; u leaves [0, 1] only for x outside the unit cube.
	void locate(float x, int &cell, float &u) const
	{
		float t = x * static_cast<float>(n - 3);
		if (!(t > -1e6f && t < 1e6f)) // NaN or far outside: keep the cast defined
			t = 0.0f;
		cell = std::clamp(static_cast<int>(std::floor(t)), 0, n - 4);
		u = t - static_cast<float>(cell);
	}

	int32_t linear(int i, int j, int k) const { return (i * n + j) * n + k; }

	void unpack(int32_t index, int &i, int &j, int &k) const
	{
		k = index % n;
		j = (index / n) % n;
		i = index / (n * n);
	}

	Eigen::Vector3f nodePosition(int i, int j, int k) const
	{
		const float d = delta();
		return {(i - 1) * d, (j - 1) * d, (k - 1) * d};
	}

	Eigen::Vector3f nodePosition(int32_t index) const
	{
		int i, j, k;
		unpack(index, i, j, k);
		return nodePosition(i, j, k);
	}

	static bool inDomain(const Eigen::Vector3f &x)
	{
		return x.x() >= 0.0f && x.x() <= 1.0f && x.y() >= 0.0f && x.y() <= 1.0f &&
		       x.z() >= 0.0f && x.z() <= 1.0f;
	}
};

} // namespace ihf
