// SPDX-License-Identifier: MIT
// ADD and ADI against hand-computed values and a brute-force nearest point.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/eval/pose_error.h"

namespace ihf {
namespace {

Eigen::Matrix3d rotZ(double deg)
{
	return Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

TEST(PoseError, AddOfPureTranslationIsItsLength)
{
	const std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {10, -3, 7}, {-50, 20, 1}, {5, 5, 5}};
	Pose gt;
	Pose est;
	est.t = {3, 4, 0};
	EXPECT_EQ(addError(est, gt, pts), 5.0);
	// Translation only: the rotation shared by both poses cancels.
	gt.R = rotZ(37);
	est.R = gt.R;
	gt.t = {100, 200, 1000};
	est.t = gt.t + Eigen::Vector3d(3, 4, 0);
	EXPECT_NEAR(addError(est, gt, pts), 5.0, 1e-12);
}

TEST(PoseError, AddOfHalfTurnAboutZ)
{
	// Rz(180) maps (x, y, z) to (-x, -y, z): each point moves 2 sqrt(x^2 + y^2):
	// 2, 4, 0 and 2 sqrt(2); the mean is (6 + 2 sqrt(2)) / 4.
	const std::vector<Eigen::Vector3f> pts = {{1, 0, 0}, {0, 2, 0}, {0, 0, 3}, {1, 1, 0}};
	Pose gt;
	Pose est;
	est.R = Eigen::Vector3d(-1, -1, 1).asDiagonal();
	EXPECT_DOUBLE_EQ(addError(est, gt, pts), (6.0 + 2.0 * std::sqrt(2.0)) / 4.0);
	// The estimate being the truth gives zero.
	EXPECT_EQ(addError(gt, gt, pts), 0.0);
}

TEST(PoseError, AdiIsZeroUnderASymmetry)
{
	// A square of points (4-fold symmetric about z) at two heights.
	std::vector<Eigen::Vector3f> pts;
	for (float z : {-2.0f, 5.0f})
		for (auto [x, y] : {std::pair{10.f, 0.f}, {0.f, 10.f}, {-10.f, 0.f}, {0.f, -10.f}})
			pts.push_back({x, y, z});

	Pose gt;
	gt.R = rotZ(20);
	gt.t = {30, -40, 800};
	Pose est = gt;
	est.R = gt.R * Eigen::Matrix3d((Eigen::Matrix3d() << 0, -1, 0, 1, 0, 0, 0, 0, 1).finished());
	EXPECT_NEAR(adiError(est, gt, pts), 0.0, 1e-9);
	// ADD sees every point moved by 10 sqrt(2).
	EXPECT_NEAR(addError(est, gt, pts), 10.0 * std::sqrt(2.0), 1e-9);

	// A small shift along z: every nearest point is the same point, 1.5 away.
	est.t += gt.R * Eigen::Vector3d(0, 0, 1.5);
	EXPECT_NEAR(adiError(est, gt, pts), 1.5, 1e-9);
}

TEST(PoseError, AdiMatchesBruteForceClosestPoints)
{
	std::mt19937 rng(7);
	std::uniform_real_distribution<float> coord(-60, 60);
	std::vector<Eigen::Vector3f> pts(800);
	for (auto &p : pts)
		p = {coord(rng), coord(rng), coord(rng)};
	ClosestPointIndex index(pts);

	for (int trial = 0; trial < 5; ++trial) {
		Pose gt;
		gt.R = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
		gt.t = {coord(rng), coord(rng), 700 + coord(rng)};
		Pose est;
		est.R = Eigen::AngleAxisd(0.3 * (trial + 1), Eigen::Vector3d(1, 2, 3).normalized()) * gt.R;
		est.t = gt.t + Eigen::Vector3d(coord(rng), coord(rng), coord(rng)) * 0.1;

		double sum = 0;
		for (const auto &p : pts) {
			const Eigen::Vector3d x = gt.apply(p.cast<double>());
			double best = INFINITY;
			for (const auto &q : pts)
				best = std::min(best, (est.apply(q.cast<double>()) - x).norm());
			sum += best;
		}
		const double brute = sum / pts.size();
		EXPECT_NEAR(index.adiError(est, gt), brute, 1e-6 * brute) << "trial " << trial;
		// ADI never exceeds ADD (the same point is one candidate).
		EXPECT_LE(index.adiError(est, gt), addError(est, gt, pts) + 1e-9);
	}
}

TEST(PoseError, EmptyIndexHasNoNearestPoint)
{
	ClosestPointIndex index({});
	EXPECT_EQ(index.nearestSquared({1, 2, 3}), INFINITY);
}

TEST(PoseError, ObjectErrorPicksItsMetric)
{
	const std::vector<Eigen::Vector3f> pts = {{10, 0, 0}, {-10, 0, 0}};
	Pose gt;
	Pose est;
	est.R = Eigen::Vector3d(-1, -1, 1).asDiagonal(); // swaps the two points
	ObjectPoseError add(pts, PoseMetric::kAdd);
	ObjectPoseError adi(pts, PoseMetric::kAdi);
	EXPECT_EQ(add.metric(), PoseMetric::kAdd);
	EXPECT_EQ(adi.metric(), PoseMetric::kAdi);
	EXPECT_EQ(add.numPoints(), 2u);
	EXPECT_EQ(adi.numPoints(), 2u);
	EXPECT_DOUBLE_EQ(add(est, gt), 20.0);
	EXPECT_DOUBLE_EQ(adi(est, gt), 0.0);
	EXPECT_STREQ(poseMetricName(PoseMetric::kAdi), "ADI");
	EXPECT_STREQ(poseMetricName(PoseMetric::kAdd), "ADD");
}

} // namespace
} // namespace ihf
