// SPDX-License-Identifier: MIT
// Greedy estimate-to-instance assignment.

#include <limits>

#include <gtest/gtest.h>

#include "core/eval/matching.h"

namespace ihf {
namespace {

TEST(Matching, DuplicateEstimateIsAFalsePositive)
{
	// Two estimates of one instance: the better scored one takes it.
	Eigen::MatrixXd errors(2, 1);
	errors << 1.0, 1.0;
	MatchResult m = matchGreedy({0.4, 0.9}, errors);
	EXPECT_EQ(m.gtOfEstimate[1], 0);
	EXPECT_EQ(m.gtOfEstimate[0], -1);
	EXPECT_EQ(m.estimateOfGt[0], 1);
	EXPECT_EQ(m.estimateError[1], 1.0);
	EXPECT_EQ(m.estimateError[0], std::numeric_limits<double>::infinity());
}

TEST(Matching, HigherScoreChoosesFirstAndTakesItsClosest)
{
	// est0 (score 0.5) is closest to gt0; est1 (score 0.8) also prefers
	// gt0 and, going first, takes it; est0 falls back to gt1.
	Eigen::MatrixXd errors(2, 2);
	errors << 1.0, 7.0,
		  2.0, 9.0;
	MatchResult m = matchGreedy({0.5, 0.8}, errors);
	EXPECT_EQ(m.gtOfEstimate[1], 0);
	EXPECT_EQ(m.gtOfEstimate[0], 1);
	EXPECT_EQ(m.estimateError[0], 7.0);
	EXPECT_EQ(m.estimateError[1], 2.0);
	EXPECT_EQ(m.estimateOfGt[0], 1);
	EXPECT_EQ(m.estimateOfGt[1], 0);
}

TEST(Matching, MissedInstancesAndNoEstimates)
{
	Eigen::MatrixXd errors(1, 3);
	errors << 5.0, 3.0, 4.0;
	MatchResult m = matchGreedy({1.0}, errors);
	EXPECT_EQ(m.gtOfEstimate[0], 1);
	EXPECT_EQ(m.estimateOfGt[0], -1);
	EXPECT_EQ(m.estimateOfGt[2], -1);

	MatchResult none = matchGreedy({}, Eigen::MatrixXd(0, 2));
	EXPECT_EQ(none.estimateOfGt, (std::vector<int>{-1, -1}));

	// No instance at all: every estimate unmatched.
	MatchResult fp = matchGreedy({0.3, 0.2}, Eigen::MatrixXd(2, 0));
	EXPECT_EQ(fp.gtOfEstimate, (std::vector<int>{-1, -1}));
}

TEST(Matching, EqualScoresKeepInputOrder)
{
	Eigen::MatrixXd errors(2, 1);
	errors << 8.0, 1.0;
	MatchResult m = matchGreedy({0.5, 0.5}, errors);
	EXPECT_EQ(m.gtOfEstimate[0], 0);
	EXPECT_EQ(m.gtOfEstimate[1], -1);
}

} // namespace
} // namespace ihf
