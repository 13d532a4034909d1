// SPDX-License-Identifier: MIT
// Blending functions against the Cox-de Boor recursion, partition of unity,
// linear precision of the lattice (which pins the node positions) and the
// derivatives against finite differences.

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/ibs/bspline_basis.h"
#include "core/ibs/ibs_eval.h"

using namespace ihf;

namespace {

// Cardinal B-spline of degree k on knots 0, 1, ..., k + 1 (Cox-de Boor).
double cardinal(int k, double t)
{
	if (k == 0)
		return t >= 0.0 && t < 1.0 ? 1.0 : 0.0;
	return (t * cardinal(k - 1, t) + (k + 1 - t) * cardinal(k - 1, t - 1.0)) / k;
}

} // namespace

TEST(BsplineBasis, MatchesCoxDeBoor)
{
	for (int s = 0; s < 100; ++s) {
		const float u = s / 100.0f;
		float b[4];
		cubicBlend(u, b);
		for (int l = 0; l < 4; ++l)
			EXPECT_NEAR(b[l], cardinal(3, u + 3 - l), 1e-6) << "u=" << u << " l=" << l;
	}
}

TEST(BsplineBasis, FirstBlendIsOneMinusUCubed)
{
	// The paper prints (1 - u^3) / 6; the spline needs (1 - u)^3 / 6.
	float b[4];
	cubicBlend(0.5f, b);
	EXPECT_FLOAT_EQ(b[0], 0.125f / 6.0f);
	cubicBlend(0.0f, b);
	EXPECT_FLOAT_EQ(b[0], 1.0f / 6.0f);
	EXPECT_FLOAT_EQ(b[1], 4.0f / 6.0f);
	EXPECT_FLOAT_EQ(b[2], 1.0f / 6.0f);
	EXPECT_FLOAT_EQ(b[3], 0.0f);
}

TEST(BsplineBasis, PartitionOfUnityAndDerivatives)
{
	for (int s = 0; s <= 200; ++s) {
		const float u = s / 200.0f;
		float b[4], d[4];
		cubicBlend(u, b);
		cubicBlendDerivative(u, d);
		EXPECT_NEAR(b[0] + b[1] + b[2] + b[3], 1.0f, 1e-6f);
		EXPECT_NEAR(d[0] + d[1] + d[2] + d[3], 0.0f, 1e-6f);
		for (int l = 0; l < 4; ++l) {
			EXPECT_GE(b[l], 0.0f);
			const double h = 1e-3;
			const double fd = (cardinal(3, u + h + 3 - l) - cardinal(3, u - h + 3 - l)) / (2 * h);
			EXPECT_NEAR(d[l], fd, 1e-4) << "u=" << u << " l=" << l;
		}
	}
}

TEST(Lattice, LocateAndIndex)
{
	const Lattice lat(13); // 10 cells of 0.1
	EXPECT_FLOAT_EQ(lat.delta(), 0.1f);
	int cell;
	float u;
	lat.locate(0.0f, cell, u);
	EXPECT_EQ(cell, 0);
	EXPECT_FLOAT_EQ(u, 0.0f);
	lat.locate(0.25f, cell, u);
	EXPECT_EQ(cell, 2);
	EXPECT_NEAR(u, 0.5f, 1e-5f);
	lat.locate(1.0f, cell, u); // last cell, u = 1
	EXPECT_EQ(cell, 9);
	EXPECT_NEAR(u, 1.0f, 1e-5f);

	int i, j, k;
	lat.unpack(lat.linear(3, 7, 11), i, j, k);
	EXPECT_EQ(i, 3);
	EXPECT_EQ(j, 7);
	EXPECT_EQ(k, 11);
	EXPECT_TRUE(lat.nodePosition(lat.linear(1, 2, 12)).isApprox(Eigen::Vector3f(0.0f, 0.1f, 1.1f)));
}

// With every node set, constant weights give a constant function (partition
// of unity in 3D) and weights equal to the node's x give f(x) = x: linear
// precision, which holds only with nodes at (j - 1) delta.
TEST(Lattice, PartitionOfUnityAndLinearPrecision)
{
	const Lattice lat(8);
	std::vector<ControlPoint> ones, ramp;
	for (int32_t idx = 0; idx < lat.nodeCount(); ++idx) {
		const Eigen::Vector3f pos = lat.nodePosition(idx);
		ones.push_back({idx, pos, 1.0f});
		ramp.push_back({idx, pos, 2.0f * pos.x() - pos.y() + 0.5f * pos.z()});
	}
	std::mt19937 rng(3);
	std::uniform_real_distribution<float> uni(0.0f, 1.0f);
	for (int s = 0; s < 200; ++s) {
		const Eigen::Vector3f x(uni(rng), uni(rng), uni(rng));
		Eigen::Vector3f g;
		EXPECT_NEAR(evaluateIbs(ones, lat, x, &g), 1.0f, 1e-5f);
		EXPECT_LT(g.norm(), 1e-4f);
		EXPECT_NEAR(evaluateIbs(ramp, lat, x, &g), 2.0f * x.x() - x.y() + 0.5f * x.z(), 1e-5f);
		EXPECT_TRUE(g.isApprox(Eigen::Vector3f(2.0f, -1.0f, 0.5f), 1e-4f)) << g.transpose();
	}
}
