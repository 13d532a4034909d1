// SPDX-License-Identifier: MIT
#include "core/estimation/candidate_pool.h"

#include <array>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace ihf {
namespace {

constexpr double kDiameter = 100.0; // near duplicates: within 5 mm and 10 deg

Hypothesis at(double x, float score, HypothesisOrigin origin = HypothesisOrigin::kRegistration, int iteration = 0)
{
	Hypothesis h;
	h.pose.t = Eigen::Vector3d(x, 0, 500);
	h.score.score = score;
	h.origin = origin;
	h.iteration = iteration;
	h.valid = true;
	return h;
}

std::vector<double> xs(std::span<const Hypothesis> list)
{
	std::vector<double> out;
	for (const Hypothesis &h : list)
		out.push_back(h.pose.t.x());
	return out;
}

class Recorder : public EstimateObserver
{
public:
	void onHypothesis(const HypothesisEvent &e) override { events.push_back(e); }
	std::vector<HypothesisEvent> events;
};

class CandidatePoolTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		pool.attach(kept, registrationKept, rivals);
		pool.beginBox(Eigen::Matrix3d::Identity(), kDiameter, 5);
	}

	std::array<Hypothesis, 3> kept{}, registrationKept{};
	std::array<RivalPose, 16> rivals{};
	CandidatePool pool;
};

TEST_F(CandidatePoolTest, KeepsTheBestDistinctByScore)
{
	EXPECT_TRUE(pool.empty());
	pool.keep(at(0, 0.5f));
	pool.keep(at(100, 0.7f));
	pool.keep(at(200, 0.6f));
	EXPECT_EQ(xs(pool.kept()), (std::vector<double>{100, 200, 0}));
	EXPECT_EQ(pool.best().score.score, 0.7f);
	// Full: a worse one is left out, a better one pushes out the worst.
	pool.keep(at(300, 0.4f));
	pool.keep(at(400, 0.8f));
	EXPECT_EQ(xs(pool.kept()), (std::vector<double>{400, 100, 200}));
}

TEST_F(CandidatePoolTest, ANearDuplicateReplacesOnlyWhenBetter)
{
	pool.keep(at(0, 0.5f));
	pool.keep(at(100, 0.6f));
	pool.keep(at(2, 0.4f)); // 2 mm from the first, worse: dropped
	EXPECT_EQ(xs(pool.kept()), (std::vector<double>{100, 0}));
	pool.keep(at(3, 0.9f)); // better: replaces it, ranked anew
	EXPECT_EQ(xs(pool.kept()), (std::vector<double>{3, 100}));
}

TEST_F(CandidatePoolTest, RefinementModesStayOutOfTheRegistrationList)
{
	pool.keep(at(0, 0.5f));
	pool.keep(at(100, 0.9f, HypothesisOrigin::kRefinement, 1));
	pool.keep(at(200, 0.8f, HypothesisOrigin::kRefinement, 2));
	pool.keep(at(300, 0.7f, HypothesisOrigin::kProposal));
	// All: the refinement's modes crowd out the registration's.
	EXPECT_EQ(xs(pool.kept()), (std::vector<double>{100, 200, 300}));
	// The polish adds the registration's own best after a refinement.
	FixedList<Hypothesis, 8> out;
	pool.polishCandidates({2, true, false}, at(0, 0.5f), at(100, 0.9f, HypothesisOrigin::kRefinement, 1), out);
	EXPECT_EQ(xs(out.items()), (std::vector<double>{100, 200, 300, 0}));
}

TEST_F(CandidatePoolTest, PolishCandidatesAddTheForestBestsOnlyAfterARefinement)
{
	pool.keep(at(0, 0.9f, HypothesisOrigin::kProposal));
	FixedList<Hypothesis, 8> out;
	const Hypothesis registration = at(100, 0.5f), refinement = at(200, 0.4f, HypothesisOrigin::kRefinement, 3);
	pool.polishCandidates({16, false, true}, registration, Hypothesis{}, out);
	EXPECT_EQ(xs(out.items()), (std::vector<double>{0}));
	pool.polishCandidates({16, false, true}, registration, refinement, out);
	EXPECT_EQ(xs(out.items()), (std::vector<double>{0, 100, 200}));
	// Not twice: a forest best among the kept is not added again.
	pool.polishCandidates({16, false, true}, at(1, 0.5f), refinement, out);
	EXPECT_EQ(xs(out.items()), (std::vector<double>{0, 200}));
	// None wanted: nothing at all.
	pool.polishCandidates({0, true, true}, registration, refinement, out);
	EXPECT_TRUE(out.empty());
}

TEST_F(CandidatePoolTest, DistinctCentresSkipNearTranslations)
{
	pool.keep(at(0, 0.9f));
	pool.keep(at(5, 0.8f, HypothesisOrigin::kProposal)); // distinct pose, same place
	pool.keep(at(100, 0.7f));
	std::array<Eigen::Vector3d, 4> centres;
	ASSERT_EQ(pool.distinctCentres(0.1 * kDiameter, centres), 2u);
	EXPECT_EQ(centres[0].x(), 0);
	EXPECT_EQ(centres[1].x(), 100);
	EXPECT_EQ(pool.distinctCentres(0.1 * kDiameter, std::span<Eigen::Vector3d>(centres.data(), 1)), 1u);
}

TEST_F(CandidatePoolTest, ReportsEachOriginsIteration)
{
	EXPECT_EQ(pool.reportedIteration(at(0, 0.5f)), 0);
	EXPECT_EQ(pool.reportedIteration(at(0, 0.5f, HypothesisOrigin::kRefinement, 3)), 3);
	// A proposal after the k = 5 refinement iterations.
	EXPECT_EQ(pool.reportedIteration(at(0, 0.5f, HypothesisOrigin::kProposal)), 6);
}

TEST_F(CandidatePoolTest, ReportsInTheRealCameraAndRecordsRivals)
{
	Recorder recorder;
	pool.setObserver(&recorder);
	const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix();
	pool.beginBox(turn, kDiameter, 2);
	const Hypothesis winner = at(0, 0.9f), rival = at(200, 0.6f, HypothesisOrigin::kProposal);
	pool.report(winner, "mode", 0, 0.25f);
	pool.report(rival, "view", 1);
	ASSERT_EQ(recorder.events.size(), 2u);
	EXPECT_STREQ(recorder.events[0].stage, "mode");
	EXPECT_EQ(recorder.events[0].voteDensity, 0.25f);
	EXPECT_TRUE(recorder.events[0].pose.t.isApprox(turn * winner.pose.t));
	EXPECT_EQ(recorder.events[1].iteration, 3);
	EXPECT_EQ(recorder.events[1].rank, 1);
	// Reported, not kept: the rival counts for the confidence only.
	EXPECT_TRUE(pool.empty());
	const std::array<Eigen::Vector3f, 1> vertices{Eigen::Vector3f::Zero()};
	EXPECT_EQ(pool.bestDistinctRival(winner.pose, vertices, Eigen::Vector3d::Zero(), false, 10.0), 0.6f);
	// A new box forgets them.
	pool.beginBox(turn, kDiameter, 2);
	EXPECT_EQ(pool.bestDistinctRival(winner.pose, vertices, Eigen::Vector3d::Zero(), false, 10.0), 0.0f);
}

TEST(TakeBetter, TakesOnlyAValidHigherScore)
{
	Hypothesis best;
	EXPECT_TRUE(takeBetter(best, at(0, 0.1f))); // anything valid beats none
	EXPECT_FALSE(takeBetter(best, at(1, 0.1f))); // a tie keeps the first
	Hypothesis invalid = at(2, 0.9f);
	invalid.valid = false;
	EXPECT_FALSE(takeBetter(best, invalid));
	EXPECT_TRUE(takeBetter(best, at(3, 0.2f)));
	EXPECT_EQ(best.pose.t.x(), 3);
}

} // namespace
} // namespace ihf
