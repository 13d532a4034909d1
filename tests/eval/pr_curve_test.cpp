// SPDX-License-Identifier: MIT
// Precision/recall sweep and best F1 on hand-computed cases.

#include <limits>

#include <gtest/gtest.h>

#include "core/eval/pr_curve.h"

namespace ihf {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(PrCurve, PerfectPosesGiveF1One)
{
	std::vector<ScoredOutcome> o = {{0.9, 0.0}, {0.5, 1.0}, {0.7, 2.0}};
	auto curve = prCurve(o, 3, 2.0);
	ASSERT_EQ(curve.size(), 3u);
	EXPECT_EQ(curve.back().precision, 1.0);
	EXPECT_EQ(curve.back().recall, 1.0);
	EXPECT_EQ(bestF1(curve), 1.0);
	EXPECT_EQ(recallAt(o, 3, 2.0), 1.0);
}

TEST(PrCurve, TenTruthsSixCorrectTwoWrongAboveTwoMissing)
{
	// 10 instances: 2 wrong estimates scored highest, 6 correct below, 2
	// instances without an estimate.
	std::vector<ScoredOutcome> o = {{0.99, 50}, {0.98, 60}};
	for (int i = 0; i < 6; ++i)
		o.push_back({0.9 - 0.1 * i, 1.0});
	auto curve = prCurve(o, 10, 5.0);
	ASSERT_EQ(curve.size(), 8u);
	// Thresholds descend; the first two points return only wrong poses.
	EXPECT_EQ(curve[0].threshold, 0.99);
	EXPECT_EQ(curve[0].precision, 0.0);
	EXPECT_EQ(curve[1].f1, 0.0);
	// Three returned, one correct: P = 1/3, R = 1/10, F1 = 2/13.
	EXPECT_DOUBLE_EQ(curve[2].precision, 1.0 / 3.0);
	EXPECT_DOUBLE_EQ(curve[2].recall, 0.1);
	EXPECT_DOUBLE_EQ(curve[2].f1, 2.0 / 13.0);
	// All eight returned: P = 6/8, R = 6/10, F1 = 0.9 / 1.35 = 2/3, the best.
	EXPECT_DOUBLE_EQ(curve[7].precision, 0.75);
	EXPECT_DOUBLE_EQ(curve[7].recall, 0.6);
	EXPECT_DOUBLE_EQ(bestF1(curve), 2.0 / 3.0);
	EXPECT_DOUBLE_EQ(recallAt(o, 10, 5.0), 0.6);
	// A stricter threshold makes everything wrong.
	EXPECT_EQ(bestF1(prCurve(o, 10, 0.5)), 0.0);
}

TEST(PrCurve, BestThresholdCanBeAboveTheLowest)
{
	// 2 instances: correct (0.9), wrong (0.8), wrong (0.7), unmatched (0.6).
	// Top 1: P 1, R 0.5, F1 2/3. All: P 1/4, R 1/2, F1 1/3.
	std::vector<ScoredOutcome> o = {{0.9, 1}, {0.8, 9}, {0.7, 9}, {0.6, kInf}};
	auto curve = prCurve(o, 2, 2.0);
	EXPECT_DOUBLE_EQ(curve[0].f1, 2.0 / 3.0);
	EXPECT_DOUBLE_EQ(curve[3].f1, 1.0 / 3.0);
	EXPECT_DOUBLE_EQ(bestF1(curve), 2.0 / 3.0);
}

TEST(PrCurve, TiedScoresFormOnePoint)
{
	std::vector<ScoredOutcome> o = {{0.5, 0}, {0.5, 10}, {0.2, 0}};
	auto curve = prCurve(o, 2, 1.0);
	ASSERT_EQ(curve.size(), 2u);
	EXPECT_DOUBLE_EQ(curve[0].precision, 0.5);
	EXPECT_DOUBLE_EQ(curve[0].recall, 0.5);
	EXPECT_DOUBLE_EQ(curve[1].precision, 2.0 / 3.0);
	EXPECT_DOUBLE_EQ(curve[1].recall, 1.0);
}

TEST(PrCurve, NothingReturnedGivesZero)
{
	EXPECT_TRUE(prCurve({}, 4, 1.0).empty());
	EXPECT_EQ(bestF1(prCurve({}, 4, 1.0)), 0.0);
	EXPECT_EQ(recallAt({}, 4, 1.0), 0.0);
	// Estimates but no ground truth: precision 0, F1 0.
	std::vector<ScoredOutcome> o = {{0.5, kInf}};
	EXPECT_EQ(bestF1(prCurve(o, 0, 1.0)), 0.0);
	EXPECT_EQ(recallAt(o, 0, 1.0), 0.0);
}

} // namespace
} // namespace ihf
