// SPDX-License-Identifier: MIT
// Half-turn proposals (not in the paper): the turns are proper half-turns
// about distinct axes of a hemisphere; a turn keeps the model's centre in
// place and undoes itself; and on a render of the LM-O can, a pose turned
// upside down is brought back by one of its two best-scoring half-turns; the
// screen on the view templates, which renders none of the 64 turns, keeps
// the one that brings it back among its best 8 and places it as a render's
// centroid would.

#include <algorithm>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/hypothesis_score.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/pose.h"
#include "core/pose/half_turns.h"
#include "core/pose/view_search.h"
#include "core/render/depth_renderer.h"
#include "core/training/view_template_builder.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

constexpr double kDeg = M_PI / 180.0;

TEST(HalfTurns, AreHalfTurnsAboutDistinctAxesOfAHemisphere)
{
	for (int count : {1, 3, 64}) {
		std::vector<Eigen::Vector3d> axes;
		for (int i = 0; i < count; ++i) {
			const Eigen::Matrix3d h = halfTurn(i, count);
			EXPECT_TRUE((h * h.transpose()).isIdentity(1e-12)) << i;
			EXPECT_NEAR(h.determinant(), 1.0, 1e-12);
			EXPECT_NEAR(rotationAngle(Eigen::Matrix3d::Identity(), h), M_PI, 1e-6) << i;
			EXPECT_TRUE((h * h).isIdentity(1e-12)) << i; // a half-turn twice is no turn
			// Its axis: the eigenvector of eigenvalue 1, i.e. (h + I) / 2's column space.
			const Eigen::Matrix3d p = 0.5 * (h + Eigen::Matrix3d::Identity());
			Eigen::Vector3d a = p.col(0).norm() > 0.5 ? p.col(0) : (p.col(1).norm() > 0.5 ? p.col(1) : p.col(2));
			a.normalize();
			if (a.z() < 0)
				a = -a;
			EXPECT_GT(a.z(), 0.0) << i;
			axes.push_back(a);
		}
		for (size_t i = 0; i < axes.size(); ++i)
			for (size_t j = 0; j < i; ++j)
				EXPECT_LT(std::abs(axes[i].dot(axes[j])), 0.999) << i << " " << j; // distinct up to sign
	}
}

// A configuration's turns: the lattice's first, unchanged, then the exact
// half-turns about the model's x, y and z axes when boxAxes is set.
TEST(HalfTurns, TheBoxAxesFollowTheLattice)
{
	HalfTurnConfig c;
	c.axes = 64;
	c.boxAxes = false;
	EXPECT_EQ(halfTurnCount(c), 64);
	c.boxAxes = true;
	ASSERT_EQ(halfTurnCount(c), 67);
	for (int i = 0; i < 64; ++i)
		EXPECT_TRUE(halfTurnOf(c, i).isApprox(halfTurn(i, 64), 1e-15)) << i;
	for (int a = 0; a < 3; ++a) {
		const Eigen::Vector3d e = Eigen::Vector3d::Unit(a);
		EXPECT_TRUE(halfTurnOf(c, 64 + a).isApprox(2.0 * e * e.transpose() - Eigen::Matrix3d::Identity(), 1e-15))
			<< a;
	}
	c.axes = 0; // the box axes alone
	EXPECT_EQ(halfTurnCount(c), 3);
	EXPECT_TRUE(halfTurnOf(c, 2).isApprox(Eigen::Vector3d(-1, -1, 1).asDiagonal().toDenseMatrix(), 1e-15));
	// ... which are a search of their own; without them or without
	// candidates there is nothing to turn.
	EXPECT_TRUE(halfTurnsEnabled(c));
	c.boxAxes = false;
	EXPECT_FALSE(halfTurnsEnabled(c));
	c.axes = 64;
	EXPECT_TRUE(halfTurnsEnabled(c));
	c.candidates = 0;
	EXPECT_FALSE(halfTurnsEnabled(c));
}

TEST(HalfTurns, KeepTheCentreInPlaceAndUndoThemselves)
{
	Pose p;
	p.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
	p.t = Eigen::Vector3d(20, -30, 800);
	const Eigen::Vector3d centre(5, -7, 40);
	for (int i = 0; i < 16; ++i) {
		const Pose q = turnedAbout(p, halfTurn(i, 16), centre);
		EXPECT_TRUE(q.apply(centre).isApprox(p.apply(centre), 1e-9)) << i;
		EXPECT_NEAR(rotationAngle(p.R, q.R), M_PI, 1e-6) << i;
		const Pose back = turnedAbout(q, halfTurn(i, 16), centre);
		EXPECT_TRUE(back.R.isApprox(p.R, 1e-9)) << i;
		EXPECT_TRUE(back.t.isApprox(p.t, 1e-9)) << i;
	}
}

// The LM-O can seen from the side at 900 mm in front of a wall, and the
// depth score of any pose of it against that scene.
class UpsideDownCan : public ::testing::Test
{
protected:
	void SetUp() override
	{
		auto loaded = loadPly(test::lmoDir() / "models" / "obj_000005.ply");
		ASSERT_TRUE(loaded) << loaded.error().message;
		mesh = std::move(*loaded);
		truth.R = (Eigen::AngleAxisd(-80 * kDeg, Eigen::Vector3d::UnitX()) *
			   Eigen::AngleAxisd(30 * kDeg, Eigen::Vector3d::UnitZ())).toRotationMatrix();
		truth.t = Eigen::Vector3d(0, 0, 900);
		renderer = std::make_unique<DepthRenderer>(mesh.vertices.size());
		scene.assign(static_cast<size_t>(K.width) * K.height, 0.0f);
		view.assign(scene.size(), 0.0f);
		ASSERT_TRUE(renderer->render(mesh, truth, K, sceneView()));
		for (float &d : scene)
			if (!(d > 0))
				d = 1100.0f; // a wall behind
	}
	ImageView<float> sceneView() { return ImageView<float>(scene.data(), K.width, K.height, K.width); }
	ImageView<float> viewImage() { return ImageView<float>(view.data(), K.width, K.height, K.width); }
	// Renders p into view.
	bool renderOf(const Pose &p)
	{
		std::fill(view.begin(), view.end(), 0.0f);
		return static_cast<bool>(renderer->render(mesh, p, K, viewImage()));
	}
	float scoreOf(const Pose &p) { return renderOf(p) ? scoreHypothesis(sceneView(), viewImage(), cfg).depthScore : 0.0f; }
	// The 64 half-turns of `from` about the model point `about`, the two
	// best-scoring first (the estimator polishes keep = 2).
	std::vector<std::pair<float, Pose>> bestTwoTurns(const Pose &from, const Eigen::Vector3d &about)
	{
		std::vector<std::pair<float, Pose>> turns;
		for (int i = 0; i < 64; ++i) {
			const Pose q = turnedAbout(from, halfTurn(i, 64), about);
			turns.emplace_back(scoreOf(q), q);
		}
		std::partial_sort(turns.begin(), turns.begin() + 2, turns.end(),
				  [](const auto &x, const auto &y) { return x.first > y.first; });
		return turns;
	}

	const CameraIntrinsics K{572.4114, 573.57043, 160.0, 120.0, 320, 240};
	const ScoreConfig cfg{};
	Mesh mesh;
	Pose truth;
	std::unique_ptr<DepthRenderer> renderer;
	std::vector<float> scene, view;
};

// The axis of half-turn i of count.
Eigen::Vector3d turnAxis(int i, int count)
{
	const Eigen::Matrix3d p = 0.5 * (halfTurn(i, count) + Eigen::Matrix3d::Identity());
	return (p.col(0).norm() > 0.5 ? p.col(0) : (p.col(1).norm() > 0.5 ? p.col(1) : p.col(2))).normalized();
}

// The can seen from the side, then the same pose turned 180 deg about its
// own horizontal axis (upside down): among the 64 half-turns of the wrong
// pose, the best by the depth score is within a few degrees of the truth
// and scores near the truth's own score.
TEST_F(UpsideDownCan, TheBestTurnOfAnUpsideDownCanIsTheTruth)
{
	const Eigen::Vector3d centre = boundingBox(mesh).centre().cast<double>();
	// Upside down: a half-turn about the model's x axis tilted by 10 deg,
	// which is none of the 64 axes.
	const Eigen::Vector3d flipAxis = Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
	const Pose wrong = turnedAbout(truth, Eigen::AngleAxisd(M_PI, flipAxis).toRotationMatrix(), centre);
	const float truthScore = scoreOf(truth), wrongScore = scoreOf(wrong);
	ASSERT_GT(truthScore, 0.9f);
	const auto turns = bestTwoTurns(wrong, centre);
	EXPECT_LT(wrongScore, truthScore - 0.2f);
	EXPECT_GT(turns[0].first, wrongScore + 0.1f);
	// Two half-turns about axes d apart compose to a turn by 2 d: one of
	// the two is as near the truth as the axis nearest the flip allows.
	double nearest = M_PI;
	for (int i = 0; i < 64; ++i)
		nearest = std::min(nearest, std::acos(std::min(1.0, std::abs(turnAxis(i, 64).dot(flipAxis)))));
	const double err = std::min(rotationAngle(turns[0].second.R, truth.R), rotationAngle(turns[1].second.R, truth.R));
	EXPECT_LT(err, 2 * nearest + 1 * kDeg) << nearest / kDeg;
	// The turns keep the centre, which the truth shares.
	EXPECT_LT((turns[0].second.t - truth.t).norm(), 1e-6);
}

// A failure seen on the synthetic can (syn200): the can turned round
// its own vertical axis, spout for handle. The lattice's axis nearest the
// model's z lies ~7 deg off it, so its best turn stays degrees from the
// truth; the turn about the box's z axis is the truth itself.
TEST_F(UpsideDownCan, TheCanTurnedRoundItsAxisComesBackExactlyAboutItsBoxAxis)
{
	const Eigen::Vector3d centre = boundingBox(mesh).centre().cast<double>();
	const Eigen::Matrix3d aboutZ = Eigen::Vector3d(-1, -1, 1).asDiagonal();
	const Pose wrong = turnedAbout(truth, aboutZ, centre);
	ASSERT_GT(rotationAngle(wrong.R, truth.R), 179 * kDeg);
	// The best-scoring turn of a configuration and its error.
	auto bestTurn = [&](const HalfTurnConfig &c, float &score) {
		score = -1;
		Pose best;
		for (int i = 0; i < halfTurnCount(c); ++i) {
			const Pose q = turnedAbout(wrong, halfTurnOf(c, i), centre);
			const float s = scoreOf(q);
			if (s > score) {
				score = s;
				best = q;
			}
		}
		return rotationAngle(best.R, truth.R);
	};
	HalfTurnConfig c;
	c.axes = 64;
	c.boxAxes = false;
	float latticeScore = 0, boxScore = 0;
	const double latticeErr = bestTurn(c, latticeScore);
	c.boxAxes = true;
	const double boxErr = bestTurn(c, boxScore);
	std::printf("lattice: %.1f deg, score %.3f; with the box axes: %.2f deg, score %.3f\n", latticeErr / kDeg,
		    latticeScore, boxErr / kDeg, boxScore);
	EXPECT_GT(latticeErr, 3 * kDeg);
	EXPECT_LT(boxErr, 1e-6);
	EXPECT_GT(boxScore, latticeScore);
	EXPECT_NEAR(boxScore, scoreOf(truth), 1e-6);
}

// The estimator's screen (HalfTurnConfig::screen): each turn of the upside
// down can placed by its nearest view template's centroid and scored
// sparsely, without a render. The turn the render-scored search brings back
// (above) is among the 8 best of the 64, and it lands within ICP's reach.
TEST_F(UpsideDownCan, TheScreenKeepsTheTurnBackAmongItsBestAndPlacesIt)
{
	const double diameter = meshDiameter(mesh);
	auto points = buildViewTemplatePoints(mesh, diameter, {320, 128});
	ASSERT_TRUE(points) << points.error().message;
	ViewTemplates templates{320, 128, *points};
	const Eigen::Vector3d centre = boundingBox(mesh).centre().cast<double>();
	const Eigen::Vector3d flipAxis = Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
	// Moved 30 mm along the can's axis as well: the placement has to undo it.
	Pose wrong = turnedAbout(truth, Eigen::AngleAxisd(M_PI, flipAxis).toRotationMatrix(), centre);
	wrong.t += wrong.R * Eigen::Vector3d(0, 0, 30);
	const ImageView<const float> obs(scene.data(), K.width, K.height, K.width);
	ViewSearchConfig vc;
	const int wrongView = nearestView(templates, wrong);
	ASSERT_GE(wrongView, 0);
	const Eigen::Vector3d shown = wrong.apply(viewCentroid(templates, wrongView));
	std::vector<std::pair<float, Pose>> turns;
	for (int i = 0; i < 64; ++i) {
		Pose p = turnedAbout(wrong, halfTurn(i, 64), centre);
		p.t += shown - p.apply(viewCentroid(templates, nearestView(templates, p)));
		Eigen::Vector3d t;
		const float s = sparsePoseScore(templates, nearestView(templates, p), vc, obs, K, p, BoxAxes{}, t);
		p.t = t;
		turns.emplace_back(s, p);
	}
	std::stable_sort(turns.begin(), turns.end(), [](const auto &x, const auto &y) { return x.first > y.first; });
	double rotErr = M_PI, offMm = 1e9;
	for (int j = 0; j < 8; ++j)
		if (rotationAngle(turns[static_cast<size_t>(j)].second.R, truth.R) < rotErr) {
			rotErr = rotationAngle(turns[static_cast<size_t>(j)].second.R, truth.R);
			offMm = (turns[static_cast<size_t>(j)].second.t - truth.t).norm();
		}
	std::printf("screen: rot %.1f deg, off %.1f mm\n", rotErr / kDeg, offMm);
	EXPECT_LT(rotErr, 25 * kDeg);
	EXPECT_LT(offMm, 25.0) << "ICP's reach: max_distance_mm 25";
	// The best of all is not the wrong pose's own neighbourhood.
	EXPECT_GT(rotationAngle(turns[0].second.R, wrong.R), 90 * kDeg);
}

} // namespace
} // namespace ihf
