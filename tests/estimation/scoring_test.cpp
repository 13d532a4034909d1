// SPDX-License-Identifier: MIT
// Hypothesis scoring pieces: the depth slabs of the first registration, the
// agreement of a pose with the given box (and its sides the scene hides),
// the outline's outliers, and the scene just outside the outline.
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/depth_windows.h"
#include "core/estimation/hypothesis_score.h"
#include "core/geometry/mesh.h"

namespace ihf {
namespace {

TEST(DepthWindows, DensestSlabFirstThenTheNextDistinctOne)
{
	// 100 x 100 box: a wall at 1500 mm (20%), the object at 790..840 mm
	// (50%), an occluder at 600 mm (30%).
	std::vector<float> px(100 * 100);
	ImageView<float> img(px.data(), 100, 100, 100);
	for (int y = 0; y < 100; ++y)
		for (int x = 0; x < 100; ++x)
			img.at(x, y) = y < 20 ? 1500.0f : (y < 70 ? 790.0f + 50.0f * x / 99.0f : 600.0f);
	std::vector<int> hist(1024);
	DepthWindow w[3];
	size_t n = findDepthWindows(img, 100.0f, hist, w);
	ASSERT_EQ(n, 3u);
	EXPECT_LE(w[0].nearMm, 790.0f);
	EXPECT_GE(w[0].farMm, 840.0f);
	EXPECT_EQ(w[0].pixels, 5000);
	EXPECT_LE(w[1].nearMm, 600.0f); // the occluder, then the wall
	EXPECT_GE(w[1].farMm, 600.0f);
	EXPECT_EQ(w[1].pixels, 3000);
	EXPECT_LE(w[2].nearMm, 1500.0f);
	EXPECT_GE(w[2].farMm, 1500.0f);

	// The object's pixels spread evenly over 790..840 mm: median 815.
	EXPECT_NEAR(windowMedianDepth(img, w[0]), 815.0f, 2.0f);
	EXPECT_NEAR(windowMedianDepth(img, w[1]), 600.0f, 2.0f);
	EXPECT_EQ(windowMedianDepth(img, DepthWindow{1000.0f, 1100.0f, 0}), 0.0f); // nothing inside
	EXPECT_EQ(windowMedianDepth(img, DepthWindow{900.0f, 900.0f, 0}), 0.0f);   // no thickness

	std::fill(px.begin(), px.end(), 0.0f);
	EXPECT_EQ(findDepthWindows(img, 100.0f, hist, w), 0u); // no depth, no window
}

TEST(DepthWindows, MedianDepthOfTheBoxCentreIgnoresTheRim)
{
	// The object (800 mm) fills the middle of the box, a table behind it
	// (880 mm) the 20-pixel rim: one 150 mm slab holds both.
	std::vector<float> px(100 * 100);
	ImageView<float> img(px.data(), 100, 100, 100);
	for (int y = 0; y < 100; ++y)
		for (int x = 0; x < 100; ++x)
			img.at(x, y) = (x < 20 || y < 20 || x >= 80 || y >= 80) ? 880.0f : 800.0f;
	const DepthWindow slab{760.0f, 910.0f, 0};
	EXPECT_NEAR(windowMedianDepth(img, slab), 880.0f, 2.5f);       // the rim outnumbers the object
	EXPECT_NEAR(windowMedianDepth(img, slab, 0.5f), 800.0f, 2.5f); // the middle half is the object
	// A window with (almost) nothing in the middle falls back to the box.
	const DepthWindow rimOnly{860.0f, 900.0f, 0};
	EXPECT_NEAR(windowMedianDepth(img, rimOnly, 0.5f), 880.0f, 1.0f);
}

Mesh unitCube(float side)
{
	Mesh m;
	for (int i = 0; i < 8; ++i)
		m.vertices.emplace_back((i & 1 ? 0.5f : -0.5f) * side, (i & 2 ? 0.5f : -0.5f) * side,
					(i & 4 ? 0.5f : -0.5f) * side);
	return m;
}

TEST(BoxAgreement, PenalisesPosesTooNearOrTooFarForTheBox)
{
	const Mesh cube = unitCube(100.0f);
	// A window of 80 x 80 px with f = 500 centred on the axis: a 100 mm
	// cube at 800 mm spans 62.5..66.7 px, inside and filling ~65% of it.
	CameraIntrinsics K{500, 500, 39.5, 39.5, 80, 80};
	ScoreConfig cfg;
	Pose p;
	p.t = Eigen::Vector3d(0, 0, 800);
	EXPECT_NEAR(boxAgreement(cube, p, K, cfg), 1.0f, 1e-6f);
	p.t.z() = 400; // too near: 125..139 px, sticks out beyond the margin
	float nearF = boxAgreement(cube, p, K, cfg);
	EXPECT_LT(nearF, 0.6f);
	p.t = Eigen::Vector3d(20, 0, 800); // ~6 px overhang, within the 8 px margin
	EXPECT_NEAR(boxAgreement(cube, p, K, cfg), 1.0f, 1e-6f);
	ScoreConfig strict = cfg;
	strict.boxMargin = 0;
	EXPECT_LT(boxAgreement(cube, p, K, strict), 0.99f);
	p.t = Eigen::Vector3d(0, 0, 800);
	p.t.z() = 2000; // too far: 25 px, covers ~10% of the box
	float farF = boxAgreement(cube, p, K, cfg);
	EXPECT_LT(farF, 0.3f);
	p.t = Eigen::Vector3d(60, 0, 800); // shifted half out of the box
	EXPECT_LT(boxAgreement(cube, p, K, cfg), 0.7f);
	p.t = Eigen::Vector3d(0, 0, -800); // behind the camera
	EXPECT_EQ(boxAgreement(cube, p, K, cfg), 0.0f);
	cfg.boxWeight = 0; // off
	p.t = Eigen::Vector3d(0, 0, 500);
	EXPECT_EQ(boxAgreement(cube, p, K, cfg), 1.0f);
}

TEST(BoxAgreement, OverhangPastAFrameBorderSideIsFree)
{
	// A box clipped by the frame's left border (60 x 80 px window): the
	// cube, 10 px left of the window centre, runs ~13 px past the left side,
	// more than the 6 px margin, and still covers most of the box.
	const Mesh cube = unitCube(100.0f);
	CameraIntrinsics K{500, 500, 29.5, 39.5, 60, 80};
	ScoreConfig cfg;
	Pose p;
	p.t = Eigen::Vector3d(-16, 0, 800);
	const float closed = boxAgreement(cube, p, K, cfg);
	EXPECT_LT(closed, 0.95f);
	OpenSides left;
	left.left = true;
	EXPECT_NEAR(boxAgreement(cube, p, K, cfg, left), 1.0f, 1e-6f);
	OpenSides right;
	right.right = true; // the wrong side: no help
	EXPECT_EQ(boxAgreement(cube, p, K, cfg, right), closed);
	// Open sides do not excuse a pose far too near for the box.
	p.t = Eigen::Vector3d(0, 0, 300);
	EXPECT_LT(boxAgreement(cube, p, K, cfg, left), 0.6f);
}

// A one-row rendering at 1000 mm whose observed depth gives the counts:
// inliers 3 mm off, outliers 200 mm behind, occluded 150 mm in front.
HypothesisScore scoreCounts(int in, int out, int occ, const ScoreConfig &cfg)
{
	const int n = in + out + occ;
	std::vector<float> ren(static_cast<size_t>(n), 1000.0f), obs(static_cast<size_t>(n), 1003.0f);
	ImageView<float> r(ren.data(), n, 1, n), o(obs.data(), n, 1, n);
	// The first pixel and the last ones are inliers (in >= 2): the
	// outliers stay off the outline.
	for (int i = 1; i <= out; ++i)
		o.at(i, 0) = 1200.0f;
	for (int i = out + 1; i <= out + occ; ++i)
		o.at(i, 0) = 850.0f;
	return scoreHypothesis(o, r, cfg);
}

TEST(HypothesisScore, TheAmodalDefaultsPreferAHiddenTruthToAPoseOnItsOccluder)
{
	// Counts traced on the synkaz Kinect benchmark (duck, image 32):
	// the truth, two thirds hidden, against a wrong pose laid on the
	// occluder 116 mm in front, which overhangs the given box (the cube
	// below, moved 40 mm sideways: ~0.85 of its extent inside). The
	// weights occluded 0.2, box power 1 (the tool's weights for
	// modal boxes) pick the occluder; the defaults, occluded pixels at 0.1
	// and the box factor to the power 1.5, pick the truth, which gains
	// with amodal boxes and loses with boxes round the visible part
	// (BENCHMARKS.md).
	const Mesh cube = unitCube(100.0f);
	const CameraIntrinsics K{500, 500, 39.5, 39.5, 80, 80};
	Pose off;
	off.t = Eigen::Vector3d(40, 0, 800);
	auto scores = [&](const ScoreConfig &cfg) {
		const float truth = scoreCounts(666, 1, 1394, cfg).depthScore;
		const float wrong = scoreCounts(1875, 16, 20, cfg).depthScore * boxAgreement(cube, off, K, cfg);
		return std::pair{truth, wrong};
	};
	const ScoreConfig defaults;
	EXPECT_EQ(defaults.occludedWeight, 0.1f);
	EXPECT_EQ(defaults.boxWeight, 1.5f);
	EXPECT_NEAR(boxAgreement(cube, off, K, defaults), 0.78f, 0.05f);
	const auto [truth, wrong] = scores(defaults);
	EXPECT_GT(truth, wrong);
	ScoreConfig heavierOcclusion;
	heavierOcclusion.occludedWeight = 0.2f;
	heavierOcclusion.boxWeight = 1.0f;
	EXPECT_NEAR(boxAgreement(cube, off, K, heavierOcclusion), 0.85f, 0.05f);
	const auto [heavyTruth, heavyWrong] = scores(heavierOcclusion);
	EXPECT_LT(heavyTruth, heavyWrong);
}

TEST(BoxAgreement, ASideHiddenByTheSceneOpensWhenAsked)
{
	// A 10 x 8 window, the rendering at 800 mm over columns 0-7: the scene
	// hides its two left columns (600 mm) and shows it elsewhere.
	std::vector<float> obs(10 * 8, 800.0f), ren(10 * 8, 0.0f);
	ImageView<float> o(obs.data(), 10, 8, 10), r(ren.data(), 10, 8, 10);
	for (int y = 0; y < 8; ++y)
		for (int x = 0; x < 8; ++x) {
			r.at(x, y) = 800.0f;
			if (x < 2)
				o.at(x, y) = 600.0f;
		}
	ScoreConfig cfg; // off by default
	OpenSides none = occludedSides(o, r, cfg, {});
	EXPECT_FALSE(none.left || none.right || none.top || none.bottom);
	cfg.boxOccludedSide = 0.5f;
	const OpenSides s = occludedSides(o, r, cfg, {});
	EXPECT_TRUE(s.left);                         // all of its band hidden
	EXPECT_FALSE(s.top || s.bottom || s.right); // 2 of 8 columns / nothing drawn
	cfg.boxOccludedSide = 0.2f;                 // a quarter of the top band is hidden
	EXPECT_TRUE(occludedSides(o, r, cfg, {}).top);
	OpenSides frame;
	frame.right = true; // a side the frame clipped stays open
	EXPECT_TRUE(occludedSides(o, r, cfg, frame).right);
	// The open side excuses overhang there (as a frame border does).
	const Mesh cube = unitCube(100.0f);
	CameraIntrinsics K{500, 500, 29.5, 39.5, 60, 80};
	Pose p;
	p.t = Eigen::Vector3d(-16, 0, 800);
	OpenSides left;
	left.left = true;
	EXPECT_LT(boxAgreement(cube, p, K, cfg), boxAgreement(cube, p, K, cfg, left));
}

TEST(HypothesisScore, CountsInliersOutliersAndOcclusion)
{
	std::vector<float> obs(4, 0.0f), ren(4, 0.0f);
	ImageView<float> o(obs.data(), 4, 1, 4), r(ren.data(), 4, 1, 4);
	r.at(0, 0) = 800; o.at(0, 0) = 805; // inlier
	r.at(1, 0) = 800; o.at(1, 0) = 900; // observed behind: outlier
	r.at(2, 0) = 800; o.at(2, 0) = 600; // observed in front: occluded
	r.at(3, 0) = 810;                   // no observation
	ScoreConfig cfg;
	cfg.outlierWeight = 3.0f;
	cfg.occludedWeight = 0.25f;
	cfg.residualWeight = 0.0f; // each inlier counts 1 (the weighting: ResidualWeightPrefersTheTighterFit)
	HypothesisScore s = scoreHypothesis(o, r, cfg);
	EXPECT_EQ(s.rendered, 4);
	EXPECT_EQ(s.compared, 3);
	EXPECT_EQ(s.inliers, 1);
	EXPECT_EQ(s.outliers, 1);
	EXPECT_EQ(s.occluded, 1);
	EXPECT_FLOAT_EQ(s.depthScore, 1.0f / 4.25f);
	EXPECT_FLOAT_EQ(s.depthMin, 800.0f);
	EXPECT_FLOAT_EQ(s.depthMax, 810.0f);
}

TEST(HypothesisScore, ResidualWeightPrefersTheTighterFit)
{
	// Two poses with the same inliers: one fits to 1 mm, the other's
	// inliers sit 8 mm off, inside the 10 mm band.
	std::vector<float> obs(4, 800.0f), tight(4, 801.0f), loose(4, 808.0f);
	ImageView<float> o(obs.data(), 4, 1, 4), rt(tight.data(), 4, 1, 4), rl(loose.data(), 4, 1, 4);
	ScoreConfig cfg;
	cfg.inlierMm = 10.0f;
	cfg.residualWeight = 0.0f;
	EXPECT_FLOAT_EQ(scoreHypothesis(o, rt, cfg).depthScore, 1.0f);
	EXPECT_FLOAT_EQ(scoreHypothesis(o, rl, cfg).depthScore, 1.0f); // a tie without the weight
	cfg.residualWeight = 1.0f;
	const HypothesisScore t = scoreHypothesis(o, rt, cfg), l = scoreHypothesis(o, rl, cfg);
	EXPECT_EQ(t.inliers, 4);
	EXPECT_EQ(l.inliers, 4);
	EXPECT_FLOAT_EQ(t.depthScore, 1.0f - 0.01f);
	EXPECT_FLOAT_EQ(l.depthScore, 1.0f - 0.64f);
	cfg.residualWeight = 0.5f;
	EXPECT_FLOAT_EQ(scoreHypothesis(o, rl, cfg).depthScore, 1.0f - 0.32f);
}

// An 18 x 18 window at `scene` mm with a 6 x 6 block drawn at 800 mm in
// its middle (pixels 6..11), where the scene is at 800 mm too.
struct OutlineScene {
	std::vector<float> obs = std::vector<float>(18 * 18), ren = std::vector<float>(18 * 18, 0.0f);
	ImageView<float> o{obs.data(), 18, 18, 18}, r{ren.data(), 18, 18, 18};
	explicit OutlineScene(float scene)
	{
		o.fill(scene);
		for (int y = 6; y < 12; ++y)
			for (int x = 6; x < 12; ++x) {
				r.at(x, y) = 800.0f;
				o.at(x, y) = 800.0f;
			}
	}
};

TEST(HypothesisScore, APoseLaidOnASurfaceThatGoesOnLosesToOneWithEdges)
{
	// The same depth fit, all inliers: on an object in front of a wall
	// 400 mm behind, every side of the outline drops away; laid on a
	// plane, the plane goes on past every side.
	ScoreConfig cfg;
	const OutlineScene object(1200.0f), plane(800.0f);
	const HypothesisScore onObject = scoreHypothesis(object.o, object.r, cfg);
	const HypothesisScore onPlane = scoreHypothesis(plane.o, plane.r, cfg);
	EXPECT_FLOAT_EQ(onObject.depthScore, onPlane.depthScore);
	EXPECT_EQ(onObject.edgeDrops, 24); // 6 pixels a side, 4 sides
	EXPECT_EQ(onObject.edgeContinues, 0);
	EXPECT_EQ(onPlane.edgeDrops, 0);
	EXPECT_EQ(onPlane.edgeContinues, 24);
	EXPECT_FLOAT_EQ(onObject.edgeFactor, 1.0f);
	// (0 + 5 x 0.1) / (24 + 5), against the share 0.1 a true pose reaches.
	EXPECT_FLOAT_EQ(onPlane.edgeFactor, 0.5f / 29.0f / 0.1f);
	EXPECT_FLOAT_EQ(onPlane.score, onPlane.depthScore * onPlane.edgeFactor);
	EXPECT_GT(onObject.score, 5.0f * onPlane.score);
	cfg.edgeShare = 0.0f; // off
	EXPECT_FLOAT_EQ(scoreHypothesis(plane.o, plane.r, cfg).score, onPlane.depthScore);
}

TEST(HypothesisScore, AnOccluderBesideTheOutlineAndTheWindowsEdgeSayNothing)
{
	// Left of the block an occluder in front, right of it the wall behind,
	// above and below the plane it lies on; the edges are looked at four
	// pixels out, two at half resolution.
	OutlineScene scene(800.0f);
	for (int y = 0; y < 18; ++y) {
		for (int x = 0; x < 6; ++x)
			scene.o.at(x, y) = 600.0f;
		for (int x = 12; x < 18; ++x)
			scene.o.at(x, y) = 1200.0f;
	}
	const ScoreConfig cfg;
	const HypothesisScore s = scoreHypothesis(scene.o, scene.r, cfg);
	EXPECT_EQ(s.edgeDrops, 6);
	EXPECT_EQ(s.edgeContinues, 12);
	// The top and bottom rows' outward pixels four rows out lie in the
	// window; a window cut two rows above the block has none there.
	const ImageView<float> cutO{scene.obs.data() + 4 * 18, 18, 14, 18};
	const ImageView<float> cutR{scene.ren.data() + 4 * 18, 18, 14, 18};
	const HypothesisScore cut = scoreHypothesis(cutO, cutR, cfg);
	EXPECT_EQ(cut.edgeDrops, 6);
	EXPECT_EQ(cut.edgeContinues, 6); // the bottom row only
	EXPECT_EQ(scoreHypothesis(cutO, cutR, cfg, 2).edgeContinues, 12); // two rows out at half resolution
}

TEST(HypothesisScore, OutliersOnTheOutlineCountOnlyWithoutTheSkip)
{
	// A 4x3 drawn block; the background (900) shows through at one pixel
	// of its outline and at its one interior pixel.
	std::vector<float> obs(6 * 5, 800.0f), ren(6 * 5, 0.0f);
	ImageView<float> o(obs.data(), 6, 5, 6), r(ren.data(), 6, 5, 6);
	for (int y = 1; y <= 3; ++y)
		for (int x = 1; x <= 4; ++x)
			r.at(x, y) = 800.0f;
	o.at(1, 2) = 900.0f; // outline (its left neighbour is not drawn)
	o.at(2, 2) = 900.0f; // interior
	ScoreConfig cfg;
	cfg.residualWeight = 0.0f;
	cfg.outlierWeight = 3.0f;
	cfg.skipEdgeOutliers = false;
	const HypothesisScore all = scoreHypothesis(o, r, cfg);
	EXPECT_EQ(all.outliers, 2);
	EXPECT_EQ(all.compared, 12);
	cfg.skipEdgeOutliers = true;
	const HypothesisScore skip = scoreHypothesis(o, r, cfg);
	EXPECT_EQ(skip.outliers, 1);
	EXPECT_EQ(skip.compared, 11);
	EXPECT_EQ(skip.inliers, 10);
	EXPECT_FLOAT_EQ(skip.depthScore, 10.0f / 13.0f);
	EXPECT_GT(skip.depthScore, all.depthScore);
}

} // namespace
} // namespace ihf
