// SPDX-License-Identifier: MIT
// The HoCP histogram: bin placement, the precomputed keys against the paper's
// formulas, translation invariance and the depth check.

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/features/hocp.h"
#include "tests/ibs/alloc_counter.h"

using namespace ihf;

namespace {

std::vector<PartCp> randomCps(int count, unsigned seed, const HocpConfig &cfg)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<float> uni(-0.3f, 0.3f);
	std::vector<PartCp> cps(count);
	for (auto &c : cps) {
		c.rel = {uni(rng), uni(rng), uni(rng)};
		c.weight = 3.0f * uni(rng);
	}
	setHocpKeys(cps, cfg);
	return cps;
}

double norm(const std::vector<float> &h)
{
	double s = 0;
	for (float v : h)
		s += v * v;
	return std::sqrt(s);
}

} // namespace

TEST(Hocp, BinPlacement)
{
	HocpConfig cfg; // 4 x 8 x 8
	ASSERT_EQ(hocpDimension(cfg), 256);
	std::vector<float> h(256);

	// The farthest point is in the last radial bin; straight up (+z) is the
	// last inclination bin; azimuth atan2(0, 0) = 0 is bin nPhi / 2.
	std::vector<PartCp> cps(2);
	cps[0].rel = {0.0f, 0.0f, 0.2f};
	// r = 0.2 * 0.05^(3/8) lies in radial bin 1 (t_r = 4 * (5/8) = 2.5 -> 2)?
	// Place it explicitly: t_r = 4 log(r / rmin) / log(20) = 1.5 -> bin 1,
	// direction (-x): inclination cos = 0 -> bin 4, azimuth pi -> bin 7.
	const float r1 = 0.2f * 0.05f * std::pow(20.0f, 1.5f / 4.0f);
	cps[1].rel = {-r1, 0.0f, 0.0f};
	setHocpKeys(cps, cfg);
	ASSERT_EQ(computeHocp(cps, cfg, h), 2);
	const float v = 1.0f / std::sqrt(2.0f);
	EXPECT_FLOAT_EQ(h[(3 * 8 + 7) * 8 + 4], v);
	EXPECT_FLOAT_EQ(h[(1 * 8 + 4) * 8 + 7], v);
	EXPECT_NEAR(norm(h), 1.0, 1e-6);

	// Closer than r_min still counts, in the first radial bin.
	cps[1].rel = {0.0f, 0.001f, 0.0f}; // azimuth pi/2 -> bin 6
	setHocpKeys(cps, cfg);
	computeHocp(cps, cfg, h);
	EXPECT_FLOAT_EQ(h[(0 * 8 + 4) * 8 + 6], v);

	EXPECT_EQ(computeHocp({}, cfg, h), 0);
	EXPECT_EQ(norm(h), 0.0);
}

TEST(Hocp, KeysAgreeWithThePaperFormulas)
{
	for (HocpWeighting w : {HocpWeighting::kCount, HocpWeighting::kAbsWeight, HocpWeighting::kSignSplit}) {
		HocpConfig cfg;
		cfg.nR = 3;
		cfg.nTheta = 6;
		cfg.nPhi = 10;
		cfg.weighting = w;
		const int dim = hocpDimension(cfg);
		EXPECT_EQ(dim, w == HocpWeighting::kSignSplit ? 360 : 180);
		const auto cps = randomCps(300, 11, cfg);
		std::vector<float> fast(dim), ref(dim);
		computeHocp(cps, cfg, fast);
		computeHocpReference(cps, cfg, ref);
		for (int i = 0; i < dim; ++i)
			EXPECT_NEAR(fast[i], ref[i], 1e-5f) << "bin " << i;
		EXPECT_NEAR(norm(fast), 1.0, 1e-5);
	}
}

TEST(Hocp, WeightingVariants)
{
	HocpConfig cfg;
	std::vector<PartCp> cps(2);
	cps[0].rel = {0.1f, 0.0f, 0.0f};
	cps[0].weight = 3.0f;
	cps[1].rel = {0.1f, 0.0f, 0.0f};
	cps[1].weight = -1.0f;
	setHocpKeys(cps, cfg);
	const int bin = (3 * 8 + 4) * 8 + 4;

	std::vector<float> h(512);
	cfg.weighting = HocpWeighting::kCount;
	computeHocp(cps, cfg, h);
	EXPECT_FLOAT_EQ(h[bin], 1.0f);

	cfg.weighting = HocpWeighting::kSignSplit;
	computeHocp(cps, cfg, h);
	EXPECT_FLOAT_EQ(h[bin], 1.0f / std::sqrt(2.0f));
	EXPECT_FLOAT_EQ(h[256 + bin], 1.0f / std::sqrt(2.0f));

	cps[1].rel = {0.0f, 0.1f, 0.0f};
	setHocpKeys(cps, cfg);
	cfg.weighting = HocpWeighting::kAbsWeight;
	computeHocp(cps, cfg, h);
	EXPECT_FLOAT_EQ(h[bin], 3.0f / std::sqrt(10.0f));
	EXPECT_FLOAT_EQ(h[(3 * 8 + 4) * 8 + 6], 1.0f / std::sqrt(10.0f));
}

// The histogram sees positions relative to the centre only: a translated
// part (coordinates on a 1/1024 grid, so the arithmetic is exact) gives the
// same histogram bit for bit.
TEST(Hocp, ExactlyTranslationInvariant)
{
	HocpConfig cfg;
	std::mt19937 rng(4);
	std::uniform_int_distribution<int> grid(0, 1023);
	const auto at = [&]() -> Eigen::Vector3f {
		return Eigen::Vector3f(grid(rng), grid(rng), grid(rng)) / 1024.0f;
	};
	const Eigen::Vector3f centre = at();
	const Eigen::Vector3f shift = Eigen::Vector3f(317, -211, 77) / 1024.0f;
	std::vector<Eigen::Vector3f> nodes(200);
	for (auto &n : nodes)
		n = at();
	std::vector<PartCp> a(nodes.size()), b(nodes.size());
	for (size_t i = 0; i < nodes.size(); ++i) {
		a[i].rel = nodes[i] - centre;
		b[i].rel = (nodes[i] + shift) - (centre + shift);
		a[i].weight = b[i].weight = static_cast<float>(i % 7) - 3.0f;
	}
	setHocpKeys(a, cfg);
	setHocpKeys(b, cfg);
	std::vector<float> ha(256), hb(256);
	computeHocp(a, cfg, ha);
	computeHocp(b, cfg, hb);
	EXPECT_EQ(ha, hb);
}

// A clean part (a plane's control points) with a planted blob of control
// points in front of it and another behind: the depth check against the
// plane's depth range removes both, giving the clean histogram exactly.
TEST(Hocp, DepthCheckRemovesPlantedOccluder)
{
	HocpConfig cfg;
	const float delta = 1.0f / 47.0f;
	std::vector<PartCp> clean;
	for (int i = -8; i <= 8; ++i)
		for (int j = -8; j <= 8; ++j)
			for (int k = -2; k <= 2; ++k) {
				PartCp c;
				// A plane tilted along x: depth rises 0.2 per unit x.
				c.rel = {i * delta, j * delta, 0.2f * i * delta + k * delta};
				c.weight = -static_cast<float>(k);
				clean.push_back(c);
			}
	setHocpKeys(clean, cfg);
	const float zMin = -0.2f * 8 * delta, zMax = 0.2f * 8 * delta; // the plane's data
	const float margin = 2.5f * delta; // the plane spans +- 3.6 delta

	std::vector<PartCp> planted = clean;
	for (int i = 0; i < 30; ++i) {
		PartCp front, back;
		front.rel = {0.01f * i - 0.15f, 0.05f, -0.25f + 0.002f * i}; // occluder
		front.weight = 1.0f;
		back.rel = {0.02f, 0.01f * i - 0.15f, 0.4f};                 // background
		back.weight = -1.0f;
		planted.push_back(front);
		planted.push_back(back);
	}
	setHocpKeys(planted, cfg);

	std::vector<float> hClean(256), hChecked(256), hPlanted(256);
	computeHocp(clean, cfg, hClean);
	computeHocp(planted, cfg, hPlanted);
	EXPECT_GT(hocpDistanceSquared(hClean, hPlanted), 1e-2f); // the blobs matter
	const int kept = computeHocpDepthChecked(planted, zMin, zMax, margin, cfg, hChecked);
	EXPECT_EQ(kept, static_cast<int>(clean.size()));
	EXPECT_EQ(hChecked, hClean);

	const size_t before = test::allocationCount();
	computeHocpDepthChecked(planted, zMin, zMax, margin, cfg, hChecked);
	computeHocp(planted, cfg, hPlanted);
	EXPECT_EQ(test::allocationCount(), before);
}
