// SPDX-License-Identifier: MIT
// Part extraction: regions of fixed and variable parts against brute force,
// the depth limit and cap, translation invariance of the whole chain
// (normalise, fit, extract, histogram) and the scale behaviour of the two
// part kinds.

#include <algorithm>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "core/features/depth_cloud.h"
#include "core/features/hocp.h"
#include "core/features/part_extractor.h"
#include "core/features/unit_cube_frame.h"
#include "core/ibs/ibs_fitter.h"
#include "tests/features/synthetic_depth.h"
#include "tests/ibs/alloc_counter.h"

using namespace ihf;
using test::lmoIntrinsics;

namespace {

// A sphere resting in front of a tilted plane, as a depth crop.
std::vector<CloudPoint> sceneCloud(bool withPlane = true)
{
	const CameraIntrinsics k = lmoIntrinsics();
	DepthImageMm depth(k.width, k.height, 0.0f);
	test::drawSphere(depth.view(), k, {10, 5, 720}, 50.0);
	if (withPlane) {
		const Eigen::Vector3d n = Eigen::Vector3d(0.0, -0.4, -1.0).normalized();
		test::drawPlane(depth.view(), k, n, n.dot(Eigen::Vector3d(0, 0, 790)));
	}
	const PixelBox box{270, 190, 110, 110};
	std::vector<CloudPoint> cloud(box.w * box.h);
	auto count = cloudFromDepth(depth.view(), k, box, DepthCloudConfig{}, cloud);
	EXPECT_TRUE(count.ok());
	cloud.resize(count.ok() ? *count : 0);
	return cloud;
}

// Normalise, fit, prepare: the chain every frame runs.
struct Chain {
	IbsFitter fitter{IbsLimits{64, 4000, 100000}};
	PartExtractor extractor{PartLimits{20000, 100000, 200 * 200}};
	IbsConfig ibs;
	UnitCubeFrame frame;
	std::vector<Eigen::Vector3f> unit, normals;
	std::vector<ControlPoint> cps = std::vector<ControlPoint>(100000);
	int cpCount = 0;

	Chain() { ibs.n = 40; }

	void run(const std::vector<CloudPoint> &cloud, float scale)
	{
		auto f = makeUnitCubeFrame(cloud, scale);
		ASSERT_TRUE(f.ok());
		frame = *f;
		unit.resize(cloud.size());
		normals.resize(cloud.size());
		toUnitCube(cloud, frame, unit, normals);
		auto stats = fitter.fit(unit, normals, ibs, cps);
		ASSERT_TRUE(stats.ok()) << stats.error().message;
		cpCount = stats->activeCount;
		PartSource src{cloud, unit, std::span<const ControlPoint>(cps.data(), cpCount), frame,
			       lmoIntrinsics(), fitter.lattice().delta()};
		ASSERT_TRUE(extractor.prepare(src).ok());
	}

	std::span<const ControlPoint> active() const { return {cps.data(), static_cast<size_t>(cpCount)}; }
};

int32_t nearestToPixel(const std::vector<CloudPoint> &cloud, int u, int v)
{
	for (size_t i = 0; i < cloud.size(); ++i)
		if (cloud[i].u == u && cloud[i].v == v)
			return static_cast<int32_t>(i);
	return -1;
}

std::set<std::tuple<float, float, float>> positions(std::span<const PartCp> cps, const Eigen::Vector3f &c)
{
	std::set<std::tuple<float, float, float>> s;
	for (const PartCp &p : cps) {
		const Eigen::Vector3f q = p.rel + c;
		s.insert({q.x(), q.y(), q.z()});
	}
	return s;
}

} // namespace

TEST(Parts, VariablePartMatchesBruteForce)
{
	const auto cloud = sceneCloud();
	Chain chain;
	chain.run(cloud, 1.0f);
	PartConfig cfg;
	cfg.kind = PartKind::kVariable;
	cfg.variableSide = 0.4f;
	cfg.maxControlPoints = 100000;
	const int32_t centre = nearestToPixel(cloud, 325, 245);
	ASSERT_GE(centre, 0);
	std::vector<PartCp> out(cfg.maxControlPoints);
	auto part = chain.extractor.extract(centre, cfg, HocpConfig{}, out);
	ASSERT_TRUE(part.ok());

	const Eigen::Vector3f c = chain.unit[centre];
	int data = 0;
	float zLo = 1e9f, zHi = -1e9f;
	for (const auto &p : chain.unit)
		if (((p - c).cwiseAbs().array() <= 0.2f).all()) {
			++data;
			zLo = std::min(zLo, p.z());
			zHi = std::max(zHi, p.z());
		}
	EXPECT_EQ(part->dataPoints, data);
	EXPECT_FLOAT_EQ(part->zMin, zLo - c.z());
	EXPECT_FLOAT_EQ(part->zMax, zHi - c.z());
	EXPECT_EQ(part->u, 325);
	EXPECT_EQ(part->v, 245);
	EXPECT_TRUE(part->centreCamera.isApprox(cloud[centre].p));

	const float margin = cfg.depthMarginCells * chain.fitter.lattice().delta();
	std::set<std::tuple<float, float, float>> want;
	for (const auto &cp : chain.active())
		if (((cp.pos - c).cwiseAbs().array() <= 0.2f).all() && cp.pos.z() >= zLo - margin &&
		    cp.pos.z() <= zHi + margin)
			want.insert({cp.pos.x(), cp.pos.y(), cp.pos.z()});
	ASSERT_GT(want.size(), 100u);
	EXPECT_EQ(part->cpTotal, static_cast<int>(want.size()));
	ASSERT_EQ(part->cpCount, want.size());
	// rel + centre reproduces the node positions (up to rounding).
	size_t matched = 0;
	for (const PartCp &p : std::span<const PartCp>(out.data(), part->cpCount)) {
		const Eigen::Vector3f q = p.rel + c;
		for (const auto &cp : chain.active())
			if ((cp.pos - q).norm() < 1e-6f) {
				++matched;
				EXPECT_EQ(cp.weight, p.weight);
				break;
			}
	}
	EXPECT_EQ(matched, want.size());
}

TEST(Parts, FixedPartMatchesBruteForce)
{
	const auto cloud = sceneCloud();
	Chain chain;
	chain.run(cloud, 1.0f);
	const PixelBox box = chain.extractor.cloudBox();
	EXPECT_EQ(box.w, 110);
	EXPECT_EQ(box.h, 110);
	PartConfig cfg;
	cfg.kind = PartKind::kFixed;
	cfg.fixedFraction = 0.5f;
	cfg.maxControlPoints = 100000;
	const int32_t centre = nearestToPixel(cloud, 320, 240);
	std::vector<PartCp> out(cfg.maxControlPoints);
	auto part = chain.extractor.extract(centre, cfg, HocpConfig{}, out);
	ASSERT_TRUE(part.ok());

	// Window of g x box pixels: |du| <= g w / 2, |dv| <= g h / 2.
	const float hw = 0.25f * box.w, hh = 0.25f * box.h;
	int data = 0;
	for (const auto &p : cloud)
		if (std::abs(p.u - 320) <= hw && std::abs(p.v - 240) <= hh)
			++data;
	EXPECT_EQ(part->dataPoints, data);

	// Every kept control point projects into the window.
	const CameraIntrinsics k = lmoIntrinsics();
	ASSERT_GT(part->cpCount, 100u);
	for (const PartCp &p : std::span<const PartCp>(out.data(), part->cpCount)) {
		const Eigen::Vector3f cam = chain.frame.toCamera(p.rel + chain.unit[centre]);
		const Eigen::Vector2d px = k.project(cam.cast<double>());
		EXPECT_LE(std::abs(px.x() - 320), hw + 1e-3);
		EXPECT_LE(std::abs(px.y() - 240), hh + 1e-3);
	}
}

TEST(Parts, CapKeepsTheRequestedControlPoints)
{
	const auto cloud = sceneCloud();
	Chain chain;
	chain.run(cloud, 1.0f);
	const int32_t centre = nearestToPixel(cloud, 325, 245);
	PartConfig cfg;
	cfg.maxControlPoints = 100000;
	std::vector<PartCp> all(cfg.maxControlPoints), capped(cfg.maxControlPoints);
	auto full = chain.extractor.extract(centre, cfg, HocpConfig{}, all);
	ASSERT_TRUE(full.ok());
	ASSERT_GT(full->cpCount, 300u);
	std::vector<float> weights;
	for (uint32_t i = 0; i < full->cpCount; ++i)
		weights.push_back(std::abs(all[i].weight));
	std::sort(weights.rbegin(), weights.rend());

	cfg.maxControlPoints = 200;
	cfg.cap = PartCap::kLargestWeight;
	cfg.countAllControlPoints = true;
	auto big = chain.extractor.extract(centre, cfg, HocpConfig{}, capped);
	ASSERT_TRUE(big.ok());
	EXPECT_EQ(big->cpCount, 200u);
	EXPECT_EQ(big->cpTotal, static_cast<int>(full->cpCount));
	float smallest = 1e9f;
	for (uint32_t i = 0; i < big->cpCount; ++i)
		smallest = std::min(smallest, std::abs(capped[i].weight));
	EXPECT_EQ(smallest, weights[199]);

	cfg.cap = PartCap::kUniform;
	cfg.countAllControlPoints = false; // the scan stops at the cap
	auto uni = chain.extractor.extract(centre, cfg, HocpConfig{}, capped);
	ASSERT_TRUE(uni.ok());
	EXPECT_EQ(uni->cpCount, 200u);
	EXPECT_EQ(uni->cpTotal, 200);
	// A subset of the full list, spread over it.
	const auto fullSet = positions(std::span<const PartCp>(all.data(), full->cpCount), {0, 0, 0});
	for (uint32_t i = 0; i < uni->cpCount; ++i) {
		const Eigen::Vector3f q = capped[i].rel;
		EXPECT_TRUE(fullSet.count({q.x(), q.y(), q.z()}));
	}
}

TEST(Parts, ExtractAllPacksThePool)
{
	const auto cloud = sceneCloud();
	Chain chain;
	chain.run(cloud, 1.0f);
	PartConfig cfg;
	cfg.stride = 8;
	std::vector<int32_t> centres(1000);
	const int nc = chain.extractor.centres(cfg, centres);
	ASSERT_GT(nc, 50);
	std::vector<Part> parts(1000);
	std::vector<PartCp> pool(1000 * cfg.maxControlPoints);
	auto count = chain.extractor.extractAll(cfg, HocpConfig{}, parts, pool);
	ASSERT_TRUE(count.ok());
	ASSERT_GT(*count, 50);
	EXPECT_LE(*count, nc);
	uint32_t next = 0;
	for (int i = 0; i < *count; ++i) {
		EXPECT_EQ(parts[i].cpOffset, next);
		next += parts[i].cpCount;
		EXPECT_LE(parts[i].cpCount, static_cast<uint32_t>(cfg.maxControlPoints));
		EXPECT_GE(parts[i].dataPoints, cfg.minDataPoints);
		EXPECT_EQ((parts[i].u - chain.extractor.cloudBox().x) % cfg.stride, 0);
	}

	std::vector<Part> few(3);
	EXPECT_EQ(chain.extractor.extractAll(cfg, HocpConfig{}, few, pool).error().code, Errc::kCapacity);

	// Per frame nothing is allocated: prepare, extract, histogram.
	PartSource src{cloud, chain.unit, chain.active(), chain.frame, lmoIntrinsics(),
		       chain.fitter.lattice().delta()};
	std::vector<float> h(256);
	const size_t before = test::allocationCount();
	ASSERT_TRUE(chain.extractor.prepare(src).ok());
	auto again = chain.extractor.extractAll(cfg, HocpConfig{}, parts, pool);
	computeHocp(std::span<const PartCp>(pool.data() + parts[0].cpOffset, parts[0].cpCount), HocpConfig{}, h);
	EXPECT_EQ(test::allocationCount(), before);
	EXPECT_TRUE(again.ok());
}

// The same cloud moved in camera space gives the same parts and histograms
// after normalisation, fit and extraction.
TEST(Parts, ChainIsTranslationInvariant)
{
	const auto cloud = sceneCloud();
	auto moved = cloud;
	for (auto &p : moved)
		p.p += Eigen::Vector3f(83.0f, -41.0f, 257.0f);

	PartConfig cfg;
	cfg.stride = 6;
	cfg.variableSide = 0.5f;
	HocpConfig hcfg;
	Chain a, b;
	a.run(cloud, 1.0f);
	b.run(moved, 1.0f);
	EXPECT_EQ(a.cpCount, b.cpCount);

	std::vector<Part> pa(2000), pb(2000);
	std::vector<PartCp> poolA(2000 * cfg.maxControlPoints), poolB(poolA.size());
	auto na = a.extractor.extractAll(cfg, hcfg, pa, poolA);
	auto nb = b.extractor.extractAll(cfg, hcfg, pb, poolB);
	ASSERT_TRUE(na.ok() && nb.ok());
	ASSERT_EQ(*na, *nb);
	ASSERT_GT(*na, 100);
	std::vector<float> ha(256), hb(256), prev(256);
	float worst = 0.0f;
	double neighbour = 0.0;
	int differing = 0;
	for (int i = 0; i < *na; ++i) {
		ASSERT_EQ(pa[i].point, pb[i].point);
		EXPECT_NEAR(pa[i].zMin, pb[i].zMin, 1e-5f);
		EXPECT_NEAR(pa[i].zMax, pb[i].zMax, 1e-5f);
		EXPECT_EQ(pa[i].dataPoints, pb[i].dataPoints);
		EXPECT_NEAR(pa[i].cpTotal, pb[i].cpTotal, 2);
		computeHocp(std::span<const PartCp>(poolA.data() + pa[i].cpOffset, pa[i].cpCount), hcfg, ha);
		computeHocp(std::span<const PartCp>(poolB.data() + pb[i].cpOffset, pb[i].cpCount), hcfg, hb);
		const float d = hocpDistanceSquared(ha, hb);
		worst = std::max(worst, d);
		differing += d > 0.0f;
		if (i > 0)
			neighbour += hocpDistanceSquared(ha, prev);
		prev = ha;
	}
	neighbour /= *na - 1;
	// Rounding (~1e-7 in the unit cube) may move a control point lying on a
	// bin border; anything beyond a couple of such moves is a real change.
	// For scale: the mean distance between neighbouring parts.
	EXPECT_LT(differing, *na / 20);
	EXPECT_LT(worst, 0.01f);
	EXPECT_GT(neighbour, 20.0 * worst);
}

// Growing the object in the unit cube (s = 1 against s = 2, as when clutter
// is removed) leaves a fixed part's pixel window unchanged but shrinks what a
// variable part covers.
TEST(Parts, VariablePartsShrinkAsTheObjectGrows)
{
	const auto cloud = sceneCloud(false);
	PartConfig variable, fixed;
	variable.kind = PartKind::kVariable;
	variable.variableSide = 0.5f;
	fixed.kind = PartKind::kFixed;
	const int32_t centre = nearestToPixel(cloud, 330, 245);
	ASSERT_GE(centre, 0);

	Chain big, small;
	big.run(cloud, 1.0f);   // object spans the cube
	small.run(cloud, 2.0f); // object spans half of it
	std::vector<PartCp> out(1000);
	auto vBig = big.extractor.extract(centre, variable, HocpConfig{}, out);
	auto vSmall = small.extractor.extract(centre, variable, HocpConfig{}, out);
	auto fBig = big.extractor.extract(centre, fixed, HocpConfig{}, out);
	auto fSmall = small.extractor.extract(centre, fixed, HocpConfig{}, out);
	ASSERT_TRUE(vBig.ok() && vSmall.ok() && fBig.ok() && fSmall.ok());

	EXPECT_EQ(fBig->dataPoints, fSmall->dataPoints);
	EXPECT_LT(vBig->dataPoints, vSmall->dataPoints);
	EXPECT_GT(vSmall->dataPoints, 0.9 * cloud.size()); // cube holds nearly all
	EXPECT_LT(vBig->dataPoints, static_cast<int>(cloud.size()) / 2);
}
