// SPDX-License-Identifier: MIT
// The reported poses of a box (rival_poses.h): the confidence's margin, the
// winner's score over the best rival that is a different pose, and the
// best distinct poses the nearly symmetric objects' comparison takes, and
// the distance between two poses that tells them apart.
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/estimation/rival_poses.h"

namespace ihf {
namespace {

Pose turnedAboutZ(double deg, const Eigen::Vector3d &t)
{
	Pose p;
	p.R = Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	p.t = t;
	return p;
}

// An L of 100 points, 100 mm along x and 50 along y: a half turn about the
// z axis through its corner (the tests' "centre", which it leaves in place)
// moves its points 80 mm on average.
std::vector<Eigen::Vector3f> lShape()
{
	std::vector<Eigen::Vector3f> v;
	for (int i = 0; i < 60; ++i)
		v.emplace_back(static_cast<float>(i) * 100.0f / 59.0f, 0.0f, 0.0f);
	for (int i = 1; i <= 40; ++i)
		v.emplace_back(0.0f, static_cast<float>(i) * 50.0f / 40.0f, 0.0f);
	return v;
}

// The distance between two poses (pose_distance.h): at most 64 of the
// vertices, evenly strided, stand for the model; a shift moves each of them
// by its length, a half turn about the L's corner by twice their distance
// from it.
TEST(PoseDistance, TheMeanDistanceOfTheSampledModelPoints)
{
	const std::vector<Eigen::Vector3f> l = lShape();
	std::array<Eigen::Vector3d, kPoseDistancePoints> points;
	const int n = sampleModelPoints(l, points);
	EXPECT_EQ(n, 50); // 100 vertices, every second one
	EXPECT_EQ(points[1], l[2].cast<double>());
	const std::span<const Eigen::Vector3d> sampled(points.data(), static_cast<size_t>(n));
	const Pose at = turnedAboutZ(0, {10, 20, 800});
	EXPECT_NEAR(meanPointDistance(at, turnedAboutZ(0, {13, 24, 800}), sampled), 5.0, 1e-9);
	double fromCorner = 0;
	for (const Eigen::Vector3d &p : sampled)
		fromCorner += p.norm();
	EXPECT_NEAR(meanPointDistance(at, turnedAboutZ(180, {10, 20, 800}), sampled), 2.0 * fromCorner / n, 1e-9);
	EXPECT_EQ(meanPointDistance(at, turnedAboutZ(90, {0, 0, 0}), {}), 0.0);

	std::vector<Eigen::Vector3f> few(l.begin(), l.begin() + 10);
	EXPECT_EQ(sampleModelPoints(few, points), 10);
	EXPECT_EQ(sampleModelPoints({}, points), 0);
}

TEST(PoseConfidence, TheScoreScaledByTheMarginUpToTheFullMargin)
{
	ConfidenceConfig c;
	c.fullMargin = 0.1f;
	EXPECT_FLOAT_EQ(poseConfidence(0.8f, 0.2f, c), 0.8f);  // a clear win keeps its score
	EXPECT_FLOAT_EQ(poseConfidence(0.8f, 0.1f, c), 0.8f);
	EXPECT_FLOAT_EQ(poseConfidence(0.8f, 0.05f, c), 0.4f); // half the margin, half the score
	EXPECT_FLOAT_EQ(poseConfidence(0.8f, 0.0f, c), 0.0f);  // a tie: a coin toss
	EXPECT_FLOAT_EQ(poseConfidence(0.8f, -0.1f, c), 0.0f);
	c.fullMargin = 0.0f; // off: the score alone
	EXPECT_FLOAT_EQ(poseConfidence(0.8f, 0.0f, c), 0.8f);
}

TEST(RivalPoses, OnlyADifferentPoseIsARival)
{
	const std::vector<Eigen::Vector3f> v = lShape();
	const Eigen::Vector3d origin(0, 0, 800);
	std::vector<RivalPose> storage(8);
	RivalPoses rivals(storage);
	const Pose winner = turnedAboutZ(0, origin);
	rivals.add(winner, 0.9f);                                      // the winner itself
	rivals.add(turnedAboutZ(3, origin + Eigen::Vector3d(2, 0, 0)), 0.88f); // near it: the same pose
	rivals.add(turnedAboutZ(180, origin), 0.7f);                    // turned half round
	rivals.add(turnedAboutZ(0, origin + Eigen::Vector3d(0, 0, 60)), 0.6f); // 60 mm behind
	EXPECT_EQ(rivals.size(), 4u);
	const Eigen::Vector3d centre(0, 0, 0);
	// 10 mm (0.1 of a 100 mm diameter): the half turn is the best rival.
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, centre, false, 10.0), 0.7f);
	// The near pose moves its points ~3 mm: a rival only under a 1 mm bar.
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, centre, false, 1.0), 0.88f);
	// No pose is 100 mm away on average: no rival, margin = the whole score.
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, centre, false, 100.0), 0.0f);
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, centre, false, 70.0), 0.7f);
	// Symmetric: the half turn about the centre is the same pose; the one
	// 60 mm behind still differs.
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, centre, true, 10.0), 0.6f);

	rivals.clear();
	EXPECT_EQ(rivals.size(), 0u);
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, centre, false, 10.0), 0.0f);
}

TEST(RivalPoses, AFullStoreKeepsTheBestScores)
{
	const std::vector<Eigen::Vector3f> v = lShape();
	std::vector<RivalPose> storage(2);
	RivalPoses rivals(storage);
	const Pose winner = turnedAboutZ(0, {0, 0, 800});
	rivals.add(turnedAboutZ(90, {0, 0, 800}), 0.5f);
	rivals.add(turnedAboutZ(180, {0, 0, 800}), 0.7f);
	rivals.add(turnedAboutZ(270, {0, 0, 800}), 0.6f); // replaces the 0.5
	rivals.add(turnedAboutZ(45, {0, 0, 800}), 0.4f);  // lower than both: dropped
	EXPECT_EQ(rivals.size(), 2u);
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, {0, 0, 0}, false, 10.0), 0.7f);
	storage[1].score = 0.0f; // the 0.7 (second slot) forgotten: the 0.6 remains
	EXPECT_FLOAT_EQ(rivals.bestDistinct(winner, v, {0, 0, 0}, false, 10.0), 0.6f);

	// Without storage nothing is kept and nothing is a rival.
	RivalPoses none;
	none.add(turnedAboutZ(180, {0, 0, 800}), 0.9f);
	EXPECT_EQ(none.size(), 0u);
	EXPECT_FLOAT_EQ(none.bestDistinct(winner, v, {0, 0, 0}, false, 10.0), 0.0f);
}

TEST(RivalPoses, TheBestDistinctPosesBestFirstEachApartFromThoseBefore)
{
	const std::vector<Eigen::Vector3f> v = lShape();
	const Eigen::Vector3d origin(0, 0, 800);
	std::vector<RivalPose> storage(8);
	RivalPoses rivals(storage);
	const Pose winner = turnedAboutZ(0, origin);
	rivals.add(winner, 0.9f);
	rivals.add(turnedAboutZ(3, origin + Eigen::Vector3d(2, 0, 0)), 0.88f);   // the winner again
	rivals.add(turnedAboutZ(0, origin + Eigen::Vector3d(0, 0, 60)), 0.6f);   // 60 mm behind
	rivals.add(turnedAboutZ(180, origin), 0.7f);                              // turned half round
	rivals.add(turnedAboutZ(178, origin + Eigen::Vector3d(1, 0, 0)), 0.75f); // the same half-turn, better
	rivals.add(turnedAboutZ(90, origin), 0.5f);

	RivalPose out[4];
	ASSERT_EQ(rivals.bestDistinctPoses(winner, v, 10.0, out), 3u);
	EXPECT_FLOAT_EQ(out[0].score, 0.75f); // the half-turn, once, at its best
	EXPECT_FLOAT_EQ(out[1].score, 0.6f);
	EXPECT_FLOAT_EQ(out[2].score, 0.5f);
	EXPECT_NEAR(out[1].pose.t.z(), 860.0, 1e-9);

	// No more than asked; none when nothing lies that far.
	EXPECT_EQ(rivals.bestDistinctPoses(winner, v, 10.0, std::span<RivalPose>(out, 1)), 1u);
	EXPECT_FLOAT_EQ(out[0].score, 0.75f);
	EXPECT_EQ(rivals.bestDistinctPoses(winner, v, 100.0, out), 0u);
	EXPECT_EQ(RivalPoses().bestDistinctPoses(winner, v, 10.0, out), 0u);
}

} // namespace
} // namespace ihf
