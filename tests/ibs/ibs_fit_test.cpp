// SPDX-License-Identifier: MIT
// The 3L fit: recovery of a sphere's zero set with both solvers, the active
// set, capacity handling, warm start and the fixed-memory promise.

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "core/ibs/ibs_eval.h"
#include "core/ibs/ibs_fitter.h"
#include "core/ibs/ibs_quality.h"
#include "tests/ibs/alloc_counter.h"

using namespace ihf;

namespace {

const Eigen::Vector3f kCentre(0.5f, 0.5f, 0.5f);
constexpr float kRadius = 0.3f;

Eigen::Vector3f randomDirection(std::mt19937 &rng)
{
	std::normal_distribution<float> nd;
	Eigen::Vector3f d(nd(rng), nd(rng), nd(rng));
	return d.normalized();
}

struct Cloud {
	std::vector<Eigen::Vector3f> points, normals;
};

Cloud sphere(int count, unsigned seed)
{
	std::mt19937 rng(seed);
	Cloud c;
	for (int i = 0; i < count; ++i) {
		const Eigen::Vector3f d = randomDirection(rng);
		c.points.push_back(kCentre + kRadius * d);
		c.normals.push_back(d);
	}
	return c;
}

IbsConfig config(IbsSolver solver)
{
	IbsConfig cfg;
	cfg.n = 30;
	cfg.maxPoints = 2000;
	cfg.solver = solver;
	return cfg;
}

// Radius where f changes sign along direction d, by bisection inside the
// band around the sphere where control points are active.
float zeroCrossing(const IbsFitter &fit, const Eigen::Vector3f &d, float band)
{
	float lo = kRadius - band, hi = kRadius + band;
	const float fHi = fit.evaluate(kCentre + hi * d);
	if (fit.evaluate(kCentre + lo * d) * fHi > 0.0f)
		return -1.0f;
	for (int it = 0; it < 40; ++it) {
		const float mid = 0.5f * (lo + hi);
		if ((fit.evaluate(kCentre + mid * d) > 0.0f) == (fHi > 0.0f))
			hi = mid;
		else
			lo = mid;
	}
	return 0.5f * (lo + hi);
}

class SphereFit : public ::testing::TestWithParam<IbsSolver>
{
};

} // namespace

TEST_P(SphereFit, RecoversZeroSet)
{
	const Cloud data = sphere(2000, 1);
	const IbsConfig cfg = config(GetParam());
	IbsFitter fitter(IbsLimits{64, 4000, 60000});
	std::vector<ControlPoint> cps(60000);
	auto stats = fitter.fit(data.points, data.normals, cfg, cps);
	ASSERT_TRUE(stats.ok()) << stats.error().message;
	EXPECT_EQ(stats->pointsUsed, 2000);
	EXPECT_EQ(stats->constraints, 6000);

	const float delta = fitter.lattice().delta();
	const bool cg = GetParam() == IbsSolver::kConjugateGradient;
	const float rmsLimit = cg ? 0.03f : 0.05f;

	// At the data.
	const IbsFitQuality q = measureFitQuality(fitter, data.points, data.normals, cfg);
	EXPECT_LT(q.rmsAtData, rmsLimit);
	EXPECT_EQ(q.signCorrect, 1.0f);

	// At unseen points of the sphere, and the sign half a cell inside/outside.
	const Cloud unseen = sphere(500, 99);
	double sum2 = 0.0;
	for (size_t i = 0; i < unseen.points.size(); ++i) {
		const float f = fitter.evaluate(unseen.points[i]) / cfg.offsetValue;
		sum2 += f * f;
		EXPECT_GT(fitter.evaluate(unseen.points[i] + 0.5f * delta * unseen.normals[i]), 0.0f);
		EXPECT_LT(fitter.evaluate(unseen.points[i] - 0.5f * delta * unseen.normals[i]), 0.0f);
	}
	EXPECT_LT(std::sqrt(sum2 / unseen.points.size()), rmsLimit);

	// The zero crossing along rays from the centre sits on the sphere.
	std::mt19937 rng(7);
	for (int r = 0; r < 100; ++r) {
		const Eigen::Vector3f d = randomDirection(rng);
		const float radius = zeroCrossing(fitter, d, 1.5f * delta);
		ASSERT_GT(radius, 0.0f) << "no sign change along the ray";
		EXPECT_NEAR(radius, kRadius, 0.1f * delta);
	}

	// The gradient at the surface points along the normal.
	for (size_t i = 0; i < 100; ++i) {
		Eigen::Vector3f g;
		fitter.evaluate(unseen.points[i], g);
		EXPECT_GT(g.normalized().dot(unseen.normals[i]), 0.95f);
	}
}

INSTANTIATE_TEST_SUITE_P(Solvers, SphereFit,
			 ::testing::Values(IbsSolver::kConjugateGradient, IbsSolver::kMultilevelBa),
			 [](const auto &info) {
				 return info.param == IbsSolver::kConjugateGradient ? "Cg" : "Mba";
			 });

// The output lists exactly the nodes whose 4x4x4 support holds a constraint,
// sorted by index, with their positions, and agrees with the fitter's own
// evaluation.
TEST(IbsFit, ActiveSetIsTheSupportOfTheConstraints)
{
	const Cloud data = sphere(40, 5);
	IbsConfig cfg = config(IbsSolver::kConjugateGradient);
	cfg.n = 12;
	cfg.maxPoints = 100;
	IbsFitter fitter(IbsLimits{16, 100, 5000});
	std::vector<ControlPoint> cps(5000);
	auto stats = fitter.fit(data.points, data.normals, cfg, cps);
	ASSERT_TRUE(stats.ok()) << stats.error().message;

	const Lattice lat(cfg.n);
	const float eps = cfg.offsetCells * lat.delta();
	std::set<int32_t> expected;
	for (size_t i = 0; i < data.points.size(); ++i)
		for (float s : {0.0f, 1.0f, -1.0f}) {
			const Eigen::Vector3f p = data.points[i] + s * eps * data.normals[i];
			int c[3];
			float u;
			for (int a = 0; a < 3; ++a)
				lat.locate(p[a], c[a], u);
			for (int l = 0; l < 4; ++l)
				for (int m = 0; m < 4; ++m)
					for (int k = 0; k < 4; ++k)
						expected.insert(lat.linear(c[0] + l, c[1] + m, c[2] + k));
		}
	ASSERT_EQ(stats->activeCount, static_cast<int>(expected.size()));
	auto it = expected.begin();
	for (int a = 0; a < stats->activeCount; ++a, ++it) {
		EXPECT_EQ(cps[a].index, *it);
		EXPECT_TRUE(cps[a].pos.isApprox(lat.nodePosition(*it)));
	}

	const std::span<const ControlPoint> out(cps.data(), stats->activeCount);
	std::mt19937 rng(2);
	for (int s = 0; s < 50; ++s) {
		const Eigen::Vector3f x = kCentre + (kRadius + 0.02f) * randomDirection(rng);
		Eigen::Vector3f g1, g2;
		EXPECT_NEAR(fitter.evaluate(x, g1), evaluateIbs(out, lat, x, &g2), 1e-5f);
		EXPECT_TRUE(g1.isApprox(g2, 1e-4f));
	}
}

TEST(IbsFit, CapacityErrorsLeaveTheFitterUsable)
{
	const Cloud data = sphere(1000, 3);
	const IbsConfig cfg = config(IbsSolver::kMultilevelBa);
	IbsFitter small(IbsLimits{64, 2000, 500});
	std::vector<ControlPoint> cps(60000);
	auto bad = small.fit(data.points, data.normals, cfg, cps);
	ASSERT_FALSE(bad.ok());
	EXPECT_EQ(bad.error().code, Errc::kCapacity);

	// A fitter that failed on its active set fits fine next time.
	IbsFitter fitter(IbsLimits{64, 2000, 60000});
	auto ok1 = fitter.fit(data.points, data.normals, cfg, cps);
	ASSERT_TRUE(ok1.ok());
	IbsConfig tooMany = cfg;
	tooMany.maxPoints = 3000;
	EXPECT_EQ(fitter.fit(data.points, data.normals, tooMany, cps).error().code, Errc::kCapacity);
	auto outSmall = fitter.fit(data.points, data.normals, cfg, std::span<ControlPoint>(cps.data(), 10));
	EXPECT_EQ(outSmall.error().code, Errc::kCapacity);
	auto ok2 = fitter.fit(data.points, data.normals, cfg, cps);
	ASSERT_TRUE(ok2.ok());
	EXPECT_EQ(ok2->activeCount, ok1->activeCount);
	EXPECT_EQ(fitter.evaluate(kCentre + kRadius * Eigen::Vector3f::UnitX()),
		  fitter.evaluate(kCentre + kRadius * Eigen::Vector3f::UnitX()));

	IbsConfig badN = cfg;
	badN.n = 65;
	EXPECT_EQ(fitter.fit(data.points, data.normals, badN, cps).error().code, Errc::kInvalidArgument);
}

TEST(IbsFit, PointsOutsideTheCubeAreSkippedAndCounted)
{
	Cloud data = sphere(500, 4);
	data.points.push_back({1.5f, 0.5f, 0.5f});
	data.normals.push_back({1.0f, 0.0f, 0.0f});
	IbsConfig cfg = config(IbsSolver::kMultilevelBa);
	IbsFitter fitter(IbsLimits{64, 2000, 60000});
	std::vector<ControlPoint> cps(60000);
	auto stats = fitter.fit(data.points, data.normals, cfg, cps);
	ASSERT_TRUE(stats.ok());
	EXPECT_EQ(stats->pointsOutside, 1);
	EXPECT_EQ(stats->pointsUsed, 500);
}

// Seeding CG with a converged solution leaves it converged: no iteration
// is needed and the weights come back unchanged.
TEST(IbsFit, WarmStartFromPreviousSolution)
{
	const Cloud data = sphere(1500, 6);
	IbsConfig cfg = config(IbsSolver::kConjugateGradient);
	cfg.cgMaxIterations = 200;
	cfg.cgTolerance = 1e-4f;
	IbsFitter fitter(IbsLimits{64, 2000, 60000});
	std::vector<ControlPoint> first(60000), second(60000);
	auto s1 = fitter.fit(data.points, data.normals, cfg, first);
	ASSERT_TRUE(s1.ok());
	ASSERT_LE(s1->relResidual, 1e-4f);

	cfg.warmStart = IbsWarmStart::kPrevious;
	auto s2 = fitter.fit(data.points, data.normals, cfg, second,
			     std::span<const ControlPoint>(first.data(), s1->activeCount));
	ASSERT_TRUE(s2.ok());
	EXPECT_LE(s2->iterations, 1);
	for (int a = 0; a < s1->activeCount; ++a)
		EXPECT_NEAR(second[a].weight, first[a].weight, 1e-3f);

	// Cold start with a small iteration cap is worse than the warm start.
	cfg.warmStart = IbsWarmStart::kZero;
	cfg.cgMaxIterations = 3;
	auto s3 = fitter.fit(data.points, data.normals, cfg, second);
	ASSERT_TRUE(s3.ok());
	EXPECT_GT(s3->relResidual, 10.0f * s2->relResidual);
}

TEST(IbsFit, FitAllocatesNothing)
{
	const Cloud data = sphere(2000, 8);
	IbsFitter fitter(IbsLimits{64, 2000, 60000});
	std::vector<ControlPoint> cps(60000);
	for (IbsSolver solver : {IbsSolver::kConjugateGradient, IbsSolver::kMultilevelBa}) {
		const IbsConfig cfg = config(solver);
		const size_t before = test::allocationCount();
		auto stats = fitter.fit(data.points, data.normals, cfg, cps);
		const float f = fitter.evaluate(kCentre);
		const size_t after = test::allocationCount();
		ASSERT_TRUE(stats.ok());
		EXPECT_EQ(after, before) << "fit() allocated";
		(void)f;
	}
}

// CG's products spread over a pool's threads give the very bits of one
// thread (each weight sums its terms in the same order), and allocate
// nothing. A half sphere crowds the constraints to one side of the
// lattice, so the shares' plane ranges are uneven.
TEST(IbsFit, ThreadsGiveTheSameBits)
{
	Cloud data = sphere(3000, 9);
	for (size_t i = 0; i < data.points.size(); ++i)
		if (data.points[i].x() > 0.6f)
			data.points[i].x() = 0.6f - 0.5f * (data.points[i].x() - 0.6f);
	IbsConfig cfg = config(IbsSolver::kConjugateGradient);
	cfg.maxPoints = 3000;
	IbsFitter one(IbsLimits{64, 3000, 60000});
	std::vector<ControlPoint> expected(60000);
	auto ref = one.fit(data.points, data.normals, cfg, expected);
	ASSERT_TRUE(ref.ok()) << ref.error().message;
	ASSERT_GT(ref->iterations, 5);

	for (int threads : {1, 2, 3, 4}) {
		WorkerPool pool(threads);
		IbsFitter fitter(IbsLimits{64, 3000, 60000, 3});
		std::vector<ControlPoint> cps(60000);
		(void)fitter.fit(data.points, data.normals, cfg, cps, {}, &pool); // warm-up
		const size_t before = test::allocationCount();
		auto stats = fitter.fit(data.points, data.normals, cfg, cps, {}, &pool);
		EXPECT_EQ(test::allocationCount(), before) << threads << " threads allocated";
		ASSERT_TRUE(stats.ok()) << stats.error().message;
		EXPECT_EQ(stats->iterations, ref->iterations) << threads << " threads";
		EXPECT_EQ(stats->relResidual, ref->relResidual) << threads << " threads";
		ASSERT_EQ(stats->activeCount, ref->activeCount);
		int differing = 0;
		for (int a = 0; a < ref->activeCount; ++a)
			differing += cps[a].index != expected[a].index || cps[a].weight != expected[a].weight;
		EXPECT_EQ(differing, 0) << threads << " threads";
	}
}
