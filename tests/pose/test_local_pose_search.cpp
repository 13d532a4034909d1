// SPDX-License-Identifier: MIT
// The score hill climbing that widens the ICP basin: it climbs a smooth
// score from 25 degrees / 12 mm off to within a degree and a millimetre,
// never returns a worse pose, and is off at 0 levels.

#include <gtest/gtest.h>

#include "core/geometry/pose.h"
#include "core/pose/local_pose_search.h"

namespace ihf {
namespace {

Pose truth()
{
	Pose p;
	p.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
	p.t = Eigen::Vector3d(30, -20, 800);
	return p;
}

float smoothScore(const Pose &p)
{
	const Pose g = truth();
	const double a = rotationAngle(p.R, g.R);
	const double d = (p.t - g.t).norm();
	return static_cast<float>(std::exp(-a * a / 0.5) * std::exp(-d * d / 800.0));
}

TEST(LocalPoseSearch, ClimbsToTheMaximumOfASmoothScore)
{
	Pose start = truth();
	start.R = Eigen::AngleAxisd(25.0 * M_PI / 180.0, Eigen::Vector3d(0, 1, 1).normalized()) * start.R;
	start.t += Eigen::Vector3d(8, -6, 7);
	LocalSearchConfig cfg;
	cfg.levels = 5;
	cfg.maxPasses = 8;
	LocalSearchResult r = localPoseSearch(start, smoothScore(start), cfg, smoothScore);
	EXPECT_LT(rotationAngle(r.pose.R, truth().R) * 180.0 / M_PI, 1.5);
	EXPECT_LT((r.pose.t - truth().t).norm(), 1.5);
	EXPECT_FLOAT_EQ(r.score, smoothScore(r.pose));
	EXPECT_GT(r.evaluations, 0);
}

TEST(LocalPoseSearch, NeverWorseAndOffAtZeroLevels)
{
	const Pose start = truth();
	LocalSearchConfig cfg;
	cfg.levels = 3;
	// At the maximum already: every move is worse, the start comes back.
	LocalSearchResult r = localPoseSearch(start, smoothScore(start), cfg, smoothScore);
	EXPECT_EQ(r.pose.t, start.t);
	EXPECT_EQ(r.score, smoothScore(start));
	cfg.levels = 0;
	int calls = 0;
	r = localPoseSearch(start, 0.0f, cfg, [&](const Pose &) { return ++calls, 1.0f; });
	EXPECT_EQ(calls, 0);
	EXPECT_EQ(r.score, 0.0f);
}

} // namespace
} // namespace ihf
