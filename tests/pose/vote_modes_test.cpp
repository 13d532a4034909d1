// SPDX-License-Identifier: MIT
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "core/geometry/rotation.h"
#include "core/pose/vote_modes.h"

namespace ihf {
namespace {

TEST(VoteModes, FindsTheClusterAmongOutliers)
{
	std::mt19937_64 rng(1);
	std::normal_distribution<float> n(0, 1);
	std::uniform_real_distribution<float> u(-200, 200);
	const Eigen::Vector3f centre(30, -20, 800);
	const Eigen::Quaternionf rot(Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1, 2, 3).normalized()));
	std::vector<CastVote> votes;
	for (int i = 0; i < 400; ++i) {
		Eigen::Quaternionf noise(Eigen::AngleAxisf(0.08f * n(rng),
							   Eigen::Vector3f(n(rng), n(rng), n(rng)).normalized()));
		Eigen::Quaternionf q = rot * noise;
		if (i & 1)
			q.coeffs() = -q.coeffs(); // the double cover must not matter
		votes.push_back({centre + 4.0f * Eigen::Vector3f(n(rng), n(rng), n(rng)), q, 1.0f});
	}
	for (int i = 0; i < 1200; ++i) {
		Eigen::Quaternionf q = Eigen::Quaternionf::UnitRandom();
		votes.push_back({Eigen::Vector3f(u(rng), u(rng), 800 + u(rng)), q, 1.0f});
	}
	std::shuffle(votes.begin(), votes.end(), rng);

	std::vector<float> scratch(votes.size());
	std::vector<uint32_t> support(votes.size());
	std::vector<Eigen::Vector4f> packed(votes.size());
	std::vector<Eigen::Vector3f> seeds(64);
	std::vector<PoseMode> modes(4);
	VoteModeConfig cfg;
	size_t found = findPoseModes(votes, cfg, {scratch, seeds, support, packed}, modes);
	ASSERT_GE(found, 1u);
	EXPECT_LT((modes[0].centre - centre).norm(), 2.0f);
	EXPECT_LT(quatAngle(modes[0].rotation, rot), 0.05f);
	for (size_t m = 1; m < found; ++m)
		EXPECT_LE(modes[m].translationDensity, modes[0].translationDensity);
}

TEST(VoteModes, KeepsTwoRotationModesPerCentre)
{
	// One translation cluster whose votes split 60/40 between two rotations
	// 180 degrees apart (a part that looks alike from both sides).
	std::mt19937_64 rng(2);
	std::normal_distribution<float> n(0, 1);
	const Eigen::Vector3f centre(0, 0, 900);
	const Eigen::Quaternionf a(Eigen::AngleAxisf(0.4f, Eigen::Vector3f::UnitY()));
	const Eigen::Quaternionf b = a * Eigen::Quaternionf(Eigen::AngleAxisf(M_PI, Eigen::Vector3f::UnitZ()));
	std::vector<CastVote> votes;
	for (int i = 0; i < 500; ++i) {
		Eigen::Quaternionf noise(Eigen::AngleAxisf(0.05f * n(rng),
							   Eigen::Vector3f(n(rng), n(rng), n(rng)).normalized()));
		votes.push_back({centre + 3.0f * Eigen::Vector3f(n(rng), n(rng), n(rng)),
				 (i % 5 < 3 ? a : b) * noise, 1.0f});
	}
	std::vector<float> scratch(votes.size());
	std::vector<uint32_t> support(votes.size());
	std::vector<Eigen::Vector4f> packed(votes.size());
	std::vector<Eigen::Vector3f> seeds(64);
	std::vector<PoseMode> modes(8);
	VoteModeConfig cfg;
	cfg.rotationModesPerCentre = 2;
	size_t found = findPoseModes(votes, cfg, {scratch, seeds, support, packed}, modes);
	ASSERT_EQ(found, 2u);
	EXPECT_LT((modes[0].centre - centre).norm(), 1.0f);
	EXPECT_EQ(modes[0].centre, modes[1].centre);
	EXPECT_LT(quatAngle(modes[0].rotation, a), 0.05f); // the denser first
	EXPECT_LT(quatAngle(modes[1].rotation, b), 0.05f);
	EXPECT_GT(modes[0].rotationDensity, modes[1].rotationDensity);

	// With one rotation mode per centre only the denser one is reported.
	cfg.rotationModesPerCentre = 1;
	found = findPoseModes(votes, cfg, {scratch, seeds, support, packed}, modes);
	ASSERT_EQ(found, 1u);
	EXPECT_LT(quatAngle(modes[0].rotation, a), 0.05f);
}

TEST(VoteModes, AWeakDistinctRotationAmongNoiseGetsAMode)
{
	// Most supporting votes are one rotation or noise; a tenth agree on a
	// third rotation. Occluded objects look like this (BENCHMARKS.md): the
	// true rotation is a weak cluster that must still reach the renderer.
	std::mt19937_64 rng(3);
	std::normal_distribution<float> n(0, 1);
	const Eigen::Vector3f centre(10, -20, 850);
	const Eigen::Quaternionf strong(Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitX()));
	const Eigen::Quaternionf weak(Eigen::AngleAxisf(2.0f, Eigen::Vector3f(1, 1, 0).normalized()));
	std::vector<CastVote> votes;
	for (int i = 0; i < 2000; ++i) {
		Eigen::Quaternionf noise(Eigen::AngleAxisf(0.05f * n(rng),
							   Eigen::Vector3f(n(rng), n(rng), n(rng)).normalized()));
		const int kind = i % 10;
		Eigen::Quaternionf q = kind < 5 ? strong * noise : kind == 5 ? weak * noise
						      : Eigen::Quaternionf(Eigen::Vector4f(n(rng), n(rng), n(rng), n(rng)).normalized());
		votes.push_back({centre + 3.0f * Eigen::Vector3f(n(rng), n(rng), n(rng)), q, 1.0f});
	}
	std::vector<float> scratch(votes.size());
	std::vector<uint32_t> support(votes.size());
	std::vector<Eigen::Vector4f> packed(votes.size());
	std::vector<Eigen::Vector3f> seeds(64);
	std::vector<PoseMode> modes(8);
	VoteModeConfig cfg;
	cfg.rotationModesPerCentre = 4;
	size_t found = findPoseModes(votes, cfg, {scratch, seeds, support, packed}, modes);
	ASSERT_GE(found, 2u);
	EXPECT_LT(quatAngle(modes[0].rotation, strong), 0.05f);
	bool weakFound = false;
	for (size_t m = 1; m < found; ++m)
		weakFound = weakFound || quatAngle(modes[m].rotation, weak) < 0.05f;
	EXPECT_TRUE(weakFound);
}

// A large object's box: 100k votes, 8 % around the centre, the rest spread
// over its slab. The translation mean shift on an even sixth of them finds
// the same centre; below the cap nothing changes at all.
TEST(VoteModes, ShiftOnAStrideOfManyVotesFindsTheSameCentre)
{
	std::mt19937_64 rng(5);
	std::normal_distribution<float> n(0, 1);
	std::uniform_real_distribution<float> u(-120, 120);
	const Eigen::Vector3f centre(-12, 25, 950);
	std::vector<CastVote> votes;
	for (int i = 0; i < 100000; ++i) {
		const bool near = i % 25 < 2;
		const Eigen::Vector3f c = near ? Eigen::Vector3f(centre + 6.0f * Eigen::Vector3f(n(rng), n(rng), n(rng)))
					       : Eigen::Vector3f(centre + Eigen::Vector3f(u(rng), u(rng), 0.4f * u(rng)));
		votes.push_back({c, Eigen::Quaternionf::UnitRandom(), 1.0f});
	}
	std::vector<float> scratch(votes.size());
	std::vector<uint32_t> support(votes.size());
	std::vector<Eigen::Vector4f> packed(votes.size());
	std::vector<Eigen::Vector3f> seeds(64);
	VoteModeConfig cfg;
	cfg.translationBandwidth = 12.0f; // 0.06 of a 200 mm object
	std::vector<PoseMode> all(4), strided(4), capped(4);
	cfg.maxShiftVotes = 0;
	ASSERT_GE(findPoseModes(votes, cfg, {scratch, seeds, support, packed}, all), 1u);
	cfg.maxShiftVotes = 16384;
	ASSERT_GE(findPoseModes(votes, cfg, {scratch, seeds, support, packed}, strided), 1u);
	EXPECT_LT((all[0].centre - centre).norm(), 3.0f);
	EXPECT_LT((strided[0].centre - all[0].centre).norm(), 2.0f);
	// Kernel mass of the stand-ins, weighed up: the same density scale.
	EXPECT_NEAR(strided[0].translationDensity / all[0].translationDensity, 1.0f, 0.15f);

	// Fewer votes than the cap: the very same modes.
	const std::span<const CastVote> few(votes.data(), 10000);
	cfg.maxShiftVotes = 0;
	const size_t a = findPoseModes(few, cfg, {scratch, seeds, support, packed}, all);
	cfg.maxShiftVotes = 16384;
	const size_t b = findPoseModes(few, cfg, {scratch, seeds, support, packed}, capped);
	ASSERT_EQ(a, b);
	for (size_t m = 0; m < a; ++m) {
		EXPECT_EQ(all[m].centre, capped[m].centre);
		EXPECT_EQ(all[m].translationDensity, capped[m].translationDensity);
	}
}

TEST(VoteModes, EmptyAndZeroWeightGiveNoMode)
{
	std::vector<CastVote> votes(10, CastVote{Eigen::Vector3f::Zero(), Eigen::Quaternionf::Identity(), 0});
	std::vector<float> scratch(votes.size());
	std::vector<uint32_t> support(votes.size());
	std::vector<Eigen::Vector4f> packed(votes.size());
	std::vector<Eigen::Vector3f> seeds(8);
	std::vector<PoseMode> modes(2);
	EXPECT_EQ(findPoseModes(votes, {}, {scratch, seeds, support, packed}, modes), 0u);
	EXPECT_EQ(findPoseModes({}, {}, {scratch, seeds, support, packed}, modes), 0u);
}

TEST(VoteModes, QuaternionAverageIsSignInvariant)
{
	Eigen::Quaternionf a(Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitX()));
	Eigen::Quaternionf b(Eigen::AngleAxisf(0.5f, Eigen::Vector3f::UnitX()));
	Eigen::Quaternionf nb;
	nb.coeffs() = -b.coeffs();
	std::vector<Eigen::Quaternionf> qs{a, nb};
	std::vector<float> w{1, 1};
	Eigen::Quaternionf m = averageQuaternion(qs, w);
	EXPECT_LT(quatAngle(m, Eigen::Quaternionf(Eigen::AngleAxisf(0.4f, Eigen::Vector3f::UnitX()))), 1e-3f);
}

// The rotation modes use a scalar Jacobi eigen-solver (the same bits on
// every target); it must agree with Eigen's solver on the principal axis,
// for spread-out sets, tight clusters and a single quaternion.
TEST(VoteModes, QuaternionAverageAgreesWithEigensSolver)
{
	std::mt19937 rng(7);
	std::normal_distribution<float> g(0.0f, 1.0f);
	for (int trial = 0; trial < 200; ++trial) {
		const int n = 1 + trial % 12;
		const float spread = trial % 3 == 0 ? 1.0f : (trial % 3 == 1 ? 0.1f : 0.01f);
		const Eigen::Quaternionf centre = Eigen::Quaternionf(g(rng), g(rng), g(rng), g(rng)).normalized();
		std::vector<Eigen::Quaternionf> qs;
		std::vector<float> w;
		Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
		for (int i = 0; i < n; ++i) {
			Eigen::Quaternionf q = centre;
			q.coeffs() += spread * Eigen::Vector4f(g(rng), g(rng), g(rng), g(rng));
			q.normalize();
			if (i % 2)
				q.coeffs() = -q.coeffs();
			qs.push_back(q);
			w.push_back(0.5f + std::abs(g(rng)));
			m += w.back() * q.coeffs() * q.coeffs().transpose();
		}
		Eigen::SelfAdjointEigenSolver<Eigen::Matrix4f> es(m);
		const Eigen::Vector4f values = es.eigenvalues();
		// With a (near) double largest eigenvalue the axis is not defined.
		if (values[3] - values[2] < 1e-3f * values[3])
			continue;
		Eigen::Quaternionf ref;
		ref.coeffs() = es.eigenvectors().col(3).normalized();
		const Eigen::Quaternionf got = averageQuaternion(qs, w);
		EXPECT_NEAR(got.norm(), 1.0f, 1e-5f) << "trial " << trial;
		EXPECT_LT(quatAngle(got, ref), 1e-3f) << "trial " << trial;
	}
}

// A pool spreads the seeds and the rotation modes over its threads; the
// modes are the same bits as with one thread, also when seeds meet modes
// found by others in their batch and when a stronger mode replaces the
// weakest (more clusters than room: 4 translation modes, then 1).
TEST(VoteModes, ThreadsFindTheSameModes)
{
	std::mt19937_64 rng(7);
	std::normal_distribution<float> n(0, 1);
	std::uniform_real_distribution<float> u(-150, 150);
	std::vector<CastVote> votes;
	for (int c = 0; c < 12; ++c) {
		const Eigen::Vector3f centre(u(rng), u(rng), 900 + u(rng));
		const Eigen::Quaternionf rot = Eigen::Quaternionf::UnitRandom();
		for (int i = 0; i < 60 + 40 * c; ++i) {
			const Eigen::Quaternionf noise(
				Eigen::AngleAxisf(0.1f * n(rng), Eigen::Vector3f(n(rng), n(rng), n(rng)).normalized()));
			votes.push_back({centre + 6.0f * Eigen::Vector3f(n(rng), n(rng), n(rng)), rot * noise,
					 0.5f + 0.5f * std::abs(n(rng))});
		}
	}
	for (int i = 0; i < 3000; ++i)
		votes.push_back({Eigen::Vector3f(u(rng), u(rng), 900 + u(rng)), Eigen::Quaternionf::UnitRandom(), 1.0f});
	std::shuffle(votes.begin(), votes.end(), rng);

	VoteModeConfig cfg;
	cfg.rotationModesPerCentre = 3;
	auto run = [&](WorkerPool *pool, size_t room) {
		const size_t others = pool ? static_cast<size_t>(pool->threads() - 1) : 0;
		std::vector<float> scratch(votes.size()), threadScratch(others * votes.size());
		std::vector<uint32_t> support(votes.size()), threadSupport(others * votes.size());
		std::vector<Eigen::Vector4f> packed(votes.size());
		std::vector<Eigen::Vector3f> seeds(64);
		std::vector<PoseMode> modes(room);
		modes.resize(findPoseModes(votes, cfg,
					   {scratch, seeds, support, packed, pool, threadScratch, threadSupport}, modes));
		return modes;
	};
	for (size_t room : {12u, 3u}) {
		const std::vector<PoseMode> one = run(nullptr, room);
		ASSERT_GE(one.size(), room / 3);
		for (int threads : {2, 3, 5}) {
			WorkerPool pool(threads);
			for (int repeat = 0; repeat < 3; ++repeat) {
				const std::vector<PoseMode> many = run(&pool, room);
				ASSERT_EQ(many.size(), one.size()) << threads << " threads";
				for (size_t m = 0; m < one.size(); ++m) {
					SCOPED_TRACE(testing::Message() << threads << " threads, room " << room << ", mode " << m);
					EXPECT_TRUE(many[m].centre == one[m].centre);
					EXPECT_TRUE(many[m].rotation.coeffs() == one[m].rotation.coeffs());
					EXPECT_EQ(many[m].translationDensity, one[m].translationDensity);
					EXPECT_EQ(many[m].rotationDensity, one[m].rotationDensity);
					EXPECT_EQ(many[m].supportWeight, one[m].supportWeight);
				}
			}
		}
	}
}

} // namespace
} // namespace ihf
