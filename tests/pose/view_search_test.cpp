


// SPDX-License-Identifier: MIT
// View templates and the rotation search over them (not in the paper): the
// templates' points lie on the surface their view sees; at a translation off
// by 20 mm in depth the search finds the rotation of a clean render, and of
// one half hidden behind an occluder; with no voted centre at all, from the
// box's ray and a depth; a sideways climb undoes a box centre off by
// millimetres, and its turns bring rotations closer than the template grid;
// it is off without turns or templates.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/pose.h"
#include "core/geometry/rotation.h"
#include "core/pose/half_turns.h"
#include "core/pose/view_search.h"
#include "core/render/depth_renderer.h"
#include "core/training/view_template_builder.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

class ViewSearchTest : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		auto mesh = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
		ASSERT_TRUE(mesh) << mesh.error().message;
		mesh_ = new Mesh(std::move(*mesh));
		diameter_ = meshDiameter(*mesh_);
		auto pts = buildViewTemplatePoints(*mesh_, diameter_, {320, 128});
		ASSERT_TRUE(pts) << pts.error().message;
		points_ = new std::vector<Eigen::Vector3f>(std::move(*pts));
	}
	static void TearDownTestSuite()
	{
		delete mesh_;
		delete points_;
	}
	static ViewTemplates templates() { return {320, 128, *points_}; }

	// Renders the mesh at pose into a Kinect frame, before a wall at
	// wallMm (0: none) as real scenes have a background.
	std::vector<float> render(const Pose &pose, float wallMm = 1150.0f) const
	{
		std::vector<float> depth(static_cast<size_t>(K_.width) * K_.height, 0.0f);
		DepthRenderer r(mesh_->vertices.size());
		EXPECT_TRUE(r.render(*mesh_, pose, K_, ImageView<float>(depth.data(), K_.width, K_.height, K_.width)));
		for (float &d : depth)
			if (!(d > 0))
				d = wallMm;
		return depth;
	}

	static Pose randomPose(std::mt19937_64 &rng)
	{
		std::normal_distribution<double> n(0, 1);
		std::uniform_real_distribution<double> u(-40, 40);
		// One draw per statement: the order of a call's arguments is
		// unspecified, and the inputs must not differ between compilers.
		Eigen::Vector4d q;
		for (int i = 0; i < 4; ++i)
			q[i] = n(rng);
		Eigen::Vector3d t;
		for (int i = 0; i < 3; ++i)
			t[i] = u(rng);
		Pose p;
		p.R = Eigen::Quaterniond(q.normalized()).toRotationMatrix();
		p.t = t + Eigen::Vector3d(0, 0, 900);
		return p;
	}

	// The object's pixels' extent in a render (nearer than the wall).
	struct Extent {
		int u0, u1, v0, v1;
	};
	Extent extent(const std::vector<float> &depth) const
	{
		Extent e{K_.width, -1, K_.height, -1};
		for (int y = 0; y < K_.height; ++y)
			for (int x = 0; x < K_.width; ++x)
				if (depth[static_cast<size_t>(y) * K_.width + x] < 1100) {
					e.u0 = std::min(e.u0, x), e.u1 = std::max(e.u1, x);
					e.v0 = std::min(e.v0, y), e.v1 = std::max(e.v1, y);
				}
		return e;
	}

	// A random rotation at 900 mm whose image extent is centred on the
	// optical axis, as in the virtual crop of an amodal box.
	Pose centredPose(std::mt19937_64 &rng, std::vector<float> &depth) const
	{
		Pose truth = randomPose(rng);
		truth.t = Eigen::Vector3d(0, 0, 900);
		for (int pass = 0; pass < 3; ++pass) {
			depth = render(truth);
			const Extent e = extent(depth);
			truth.t.x() -= (0.5 * (e.u0 + e.u1) - K_.cx) * truth.t.z() / K_.fx;
			truth.t.y() -= (0.5 * (e.v0 + e.v1) - K_.cy) * truth.t.z() / K_.fy;
		}
		depth = render(truth);
		return truth;
	}

	static bool near(const ViewProposal *top, size_t n, const Pose &truth, double mm)
	{
		for (size_t j = 0; j < n; ++j)
			if (rotationAngle(top[j].pose.R, truth.R) * 180.0 / M_PI < 20 && (top[j].pose.t - truth.t).norm() < mm)
				return true;
		return false;
	}

	// Whether one search's (at most 6) proposals hold the truth (near()).
	static bool finds(const ViewSearchConfig &cfg, ImageView<const float> view, const CameraIntrinsics &K,
			  const Eigen::Vector3d &centre, const Pose &truth, double mm, BoxAxes box = {},
			  float anchor = 0.0f)
	{
		ViewProposal top[6];
		return near(top, searchViews(templates(), cfg, view, K, centre, top, box, anchor), truth, mm);
	}

	// A window of the frame, as a virtual crop's: its depth and intrinsics.
	struct Window {
		std::vector<float> depth;
		CameraIntrinsics K;
		Eigen::Vector3d voted; // clippedWindow()'s only
		ImageView<const float> view() const { return {depth.data(), K.width, K.height, K.width}; }
	};
	// The window of a box the frame clipped: the object's extent (in `full`)
	// with its left third cut off by the frame and `margin` of its width
	// past its right side; rows centred on the principal point as the
	// virtual crop's, 5 % past the extent. `voted`: the window's centre ray
	// at the truth's depth + 20 mm.
	Window clippedWindow(const std::vector<float> &full, const Pose &truth, double margin) const
	{
		const auto [u0, u1, v0, v1] = extent(full);
		const int mx = static_cast<int>(margin * (u1 - u0)), my = (v1 - v0) / 20;
		const int x0 = u0 + (u1 - u0) / 3, x1 = u1 + mx;
		const int half = std::max(static_cast<int>(K_.cy) - v0, v1 - static_cast<int>(K_.cy)) + my;
		const int y0 = static_cast<int>(K_.cy) - half, y1 = static_cast<int>(K_.cy) + half;
		const int w = x1 - x0 + 1, h = y1 - y0 + 1;
		Window c{std::vector<float>(static_cast<size_t>(w) * h), K_, {}};
		for (int y = 0; y < h; ++y)
			for (int x = 0; x < w; ++x)
				c.depth[static_cast<size_t>(y) * w + x] = full[static_cast<size_t>(y + y0) * K_.width + x + x0];
		c.K.cx -= x0;
		c.K.cy -= y0;
		c.K.width = w;
		c.K.height = h;
		c.voted = c.K.backProject(0.5 * (w - 1), 0.5 * (h - 1), truth.t.z() + 20);
		return c;
	}

	// The window of an amodal box round the object in `full`: its extent,
	// 5 % wider on each side, `scale` times that, centred on the principal
	// point as the virtual crop's. With occluderMm > 0 the window's left
	// half lies behind an occluder at that depth; pixels past the frame are
	// the wall (1150 mm, as render()'s).
	Window boxWindow(const std::vector<float> &full, int scale = 1, float occluderMm = 0.0f) const
	{
		const Extent e = extent(full);
		const int halfW = scale * ((e.u1 - e.u0) * 21 / 40 + 1), halfH = scale * ((e.v1 - e.v0) * 21 / 40 + 1);
		const int x0 = static_cast<int>(K_.cx) - halfW, y0 = static_cast<int>(K_.cy) - halfH;
		const int w = 2 * halfW + 1, h = 2 * halfH + 1;
		Window c{std::vector<float>(static_cast<size_t>(w) * h, 1150.0f), K_, {}};
		for (int y = 0; y < h; ++y)
			for (int x = 0; x < w; ++x) {
				float &d = c.depth[static_cast<size_t>(y) * w + x];
				if (occluderMm > 0 && x < w / 2)
					d = occluderMm;
				else if (x + x0 >= 0 && x + x0 < K_.width && y + y0 >= 0 && y + y0 < K_.height)
					d = full[static_cast<size_t>(y + y0) * K_.width + x + x0];
			}
		c.K.cx -= x0;
		c.K.cy -= y0;
		c.K.width = w;
		c.K.height = h;
		return c;
	}

	static Mesh *mesh_;
	static double diameter_;
	static std::vector<Eigen::Vector3f> *points_;
	CameraIntrinsics K_ = kinectV1Intrinsics();
};

Mesh *ViewSearchTest::mesh_ = nullptr;
double ViewSearchTest::diameter_ = 0;
std::vector<Eigen::Vector3f> *ViewSearchTest::points_ = nullptr;

TEST_F(ViewSearchTest, TemplatePointsLieOnTheSurfaceTheirViewSees)
{
	const ViewTemplates t = templates();
	ASSERT_EQ(points_->size(), 320u * 128u);
	int checked = 0, visible = 0;
	for (int v = 0; v < t.viewpoints; v += 7) {
		Pose pose;
		pose.R = viewRotation(t, 1, v, 0);
		pose.t = Eigen::Vector3d(0, 0, 800);
		const std::vector<float> depth = render(pose, 0.0f);
		for (const Eigen::Vector3f &p : t.view(v)) {
			const Eigen::Vector3d c = pose.apply(p.cast<double>());
			const Eigen::Vector2d uv = K_.project(c);
			const int x = static_cast<int>(std::lround(uv.x())), y = static_cast<int>(std::lround(uv.y()));
			ASSERT_TRUE(x >= 0 && y >= 0 && x < K_.width && y < K_.height);
			++checked;
			// Seen from its view, the point is the surface at its pixel (a
			// pixel's footprint on a slanted surface: a few mm).
			visible += std::abs(depth[static_cast<size_t>(y) * K_.width + x] - c.z()) < 4.0;
		}
	}
	EXPECT_GT(visible, checked * 95 / 100) << visible << " of " << checked;
}

TEST_F(ViewSearchTest, FindsTheRotationOfACleanRenderFromAnOffDepth)
{
	std::mt19937_64 rng(7);
	ViewSearchConfig cfg;
	cfg.inplane = 24;
	cfg.keep = 6;
	int bestNear = 0, anyNear = 0, depthOk = 0;
	const int trials = 12;
	for (int i = 0; i < trials; ++i) {
		const Pose truth = randomPose(rng);
		const std::vector<float> depth = render(truth);
		ViewProposal top[6];
		// The voted centre is often off in depth by a part's offset error.
		const size_t n = searchViews(templates(), cfg, ImageView<const float>(depth.data(), K_.width, K_.height, K_.width),
					     K_, truth.t + Eigen::Vector3d(0, 0, 20), top, BoxAxes{false, false, {}});
		ASSERT_GT(n, 0u);
		const double deg = 180.0 / M_PI;
		bestNear += rotationAngle(top[0].pose.R, truth.R) * deg < 20;
		bool near = false;
		for (size_t j = 0; j < n; ++j)
			near = near || rotationAngle(top[j].pose.R, truth.R) * deg < 20;
		anyNear += near;
		depthOk += std::abs(top[0].pose.t.z() - truth.t.z()) < 10;
	}
	// 320 directions x 24 turns: the nearest rotation is within ~10 deg.
	EXPECT_GE(anyNear, trials - 1);
	EXPECT_GE(bestNear, trials * 3 / 4);
	EXPECT_GE(depthOk, trials * 3 / 4);
}

TEST_F(ViewSearchTest, FindsTheRotationOfAHalfOccludedObject)
{
	// An occluder 150 mm in front hides the left of the box: the object's
	// left half and the background beside it. The voted centre is off
	// sideways and in depth.
	std::mt19937_64 rng(11);
	ViewSearchConfig cfg;
	cfg.inplane = 24;
	cfg.keep = 6;
	int found = 0;
	const int trials = 12;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> depth;
		const Pose truth = centredPose(rng, depth);
		const int cut = static_cast<int>(K_.cx);
		for (int y = 0; y < K_.height; ++y)
			for (int x = 0; x < cut; ++x)
				depth[static_cast<size_t>(y) * K_.width + x] = static_cast<float>(truth.t.z() - 150);
		ViewProposal top[6];
		const size_t n = searchViews(templates(), cfg, ImageView<const float>(depth.data(), K_.width, K_.height, K_.width),
					     K_, truth.t + Eigen::Vector3d(15, -10, -15), top);
		found += near(top, n, truth, 15);
	}
	RecordProperty("found", found);
	EXPECT_GE(found, trials / 2);
}

TEST_F(ViewSearchTest, BoxCentringRecoversALateralOffset)
{
	// The frame's optical axis through the centre of the object's image
	// extent plays the virtual crop of its box; the voted centre is 25 mm
	// off sideways, which the depth alignment alone cannot undo.
	std::mt19937_64 rng(5);
	ViewSearchConfig cfg;
	cfg.inplane = 24;
	cfg.keep = 6;
	int found = 0, foundWithoutBox = 0;
	const int trials = 10;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> depth;
		const Pose truth = centredPose(rng, depth);
		const Eigen::Vector3d voted = truth.t + Eigen::Vector3d(25, -20, 10);
		ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
		found += finds(cfg, view, K_, voted, truth, 15);
		foundWithoutBox += finds(cfg, view, K_, voted, truth, 15, BoxAxes{false, false, {}});
	}
	RecordProperty("found", found);
	RecordProperty("found_without_box", foundWithoutBox);
	EXPECT_GE(found, trials * 7 / 10);
	EXPECT_GT(found, foundWithoutBox + 2);
}

// A box the frame clipped: the object's left third lies past the image's
// left edge. The window is the clipped box, so its centre is not the
// object's on x; the model's points past that edge are unseen, not outside
// the box (else a pose pushed back in depth, smaller, fits the window
// better), and the rotation is placed against the box's right side.
TEST_F(ViewSearchTest, ABoxClippedByTheFrameFindsTheObjectPastItsEdge)
{
	std::mt19937_64 rng(29);
	ViewSearchConfig cfg;
	cfg.inplane = 24;
	cfg.keep = 6;
	// The placement against the edge alone. With the placements inside it
	// too (the default) this box, only 5 % larger than the object, is found
	// less often on these clean renders (10 of 16 against 14 when measured:
	// more placements, more wrong rotations at the sparse score's ceiling),
	// while on the benchmarks' boxes at the frame's border they gained
	// (BENCHMARKS.md); that cost is bounded below.
	cfg.edgeInsets = 0;
	ViewSearchConfig inside = cfg;
	inside.edgeInsets = ViewSearchConfig{}.edgeInsets;
	int found = 0, foundAsClosed = 0, foundInside = 0;
	const int trials = 16;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> full;
		const Pose truth = centredPose(rng, full);
		// The box: the extent 10 % larger, its left third cut off.
		const Window c = clippedWindow(full, truth, 0.05);
		const ImageView<const float> view = c.view();
		const CameraIntrinsics &K = c.K;
		const Eigen::Vector3d &voted = c.voted;
		const BoxAxes clipped{false, true, OpenSides{.left = true}};
		found += finds(cfg, view, K, voted, truth, 15, clipped);
		foundAsClosed += finds(cfg, view, K, voted, truth, 15, BoxAxes{false, true, {}});
		foundInside += finds(inside, view, K, voted, truth, 15, clipped);
	}
	RecordProperty("found", found);
	RecordProperty("found_as_closed", foundAsClosed);
	RecordProperty("found_inside", foundInside);
	EXPECT_GE(found, trials * 7 / 10);
	EXPECT_GT(found, foundAsClosed + 2);
	EXPECT_GE(foundInside, trials / 2);
}

// The same with a box drawn with a wide margin, a quarter of the object's
// width past its right side (ihf synth's boxes are 5-25 % larger and shifted
// by up to 10 %): placed against the box's right side, the true rotation
// sits that far off, too far for the climb, and wrong rotations outscore it;
// placed also inside that side (edgeInsets) it is found.
TEST_F(ViewSearchTest, AClippedBoxWithAMarginIsSearchedInsideItsEdgeToo)
{
	std::mt19937_64 rng(31);
	ViewSearchConfig inside;
	inside.inplane = 24;
	inside.keep = 6;
	ViewSearchConfig edge = inside;
	edge.edgeInsets = 0;
	int found = 0, foundAtEdge = 0;
	const int trials = 16;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> full;
		const Pose truth = centredPose(rng, full);
		const Window c = clippedWindow(full, truth, 0.25);
		const BoxAxes clipped{false, true, OpenSides{.left = true}};
		found += finds(inside, c.view(), c.K, c.voted, truth, 15, clipped);
		foundAtEdge += finds(edge, c.view(), c.K, c.voted, truth, 15, clipped);
	}
	RecordProperty("found", found);
	RecordProperty("found_at_edge", foundAtEdge);
	EXPECT_GE(found, trials / 2);
	EXPECT_GT(found, foundAtEdge + 4);
}

TEST_F(ViewSearchTest, ProposalsAreDistinctAndBestFirst)
{
	std::mt19937_64 rng(3);
	const Pose truth = randomPose(rng);
	const std::vector<float> depth = render(truth);
	ViewSearchConfig cfg;
	cfg.inplane = 24;
	cfg.distinctDeg = 20;
	ViewProposal top[8];
	const size_t n = searchViews(templates(), cfg, ImageView<const float>(depth.data(), K_.width, K_.height, K_.width),
				     K_, truth.t, top, BoxAxes{false, false, {}});
	ASSERT_EQ(n, 8u);
	for (size_t i = 0; i < n; ++i) {
		if (i > 0) {
			EXPECT_GE(top[i - 1].score, top[i].score);
		}
		for (size_t j = i + 1; j < n; ++j)
			EXPECT_GE(rotationAngle(top[i].pose.R, top[j].pose.R) * 180.0 / M_PI, 20.0 - 1e-6);
	}
}

// The coarse pass only chooses what the full score sees: keeping every
// rotation gives exactly the one-pass answer; the default keeps 1024 of 7680
// and still finds the rotation.
TEST_F(ViewSearchTest, CoarseToFineKeepingEverythingEqualsOnePass)
{
	std::mt19937_64 rng(19);
	const Pose truth = randomPose(rng);
	const std::vector<float> depth = render(truth);
	ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
	ViewSearchConfig cfg;
	cfg.inplane = 6; // 1920 rotations, all kept by the coarse pass
	cfg.coarseKeep = kMaxCoarseKeep;
	ViewProposal two[6], one[6];
	const Eigen::Vector3d voted = truth.t + Eigen::Vector3d(5, 5, 20);
	const size_t n2 = searchViews(templates(), cfg, view, K_, voted, two);
	cfg.coarsePoints = 0;
	const size_t n1 = searchViews(templates(), cfg, view, K_, voted, one);
	ASSERT_EQ(n1, n2);
	ASSERT_GT(n1, 0u);
	for (size_t i = 0; i < n1; ++i) {
		EXPECT_EQ(one[i].view, two[i].view);
		EXPECT_EQ(one[i].turn, two[i].turn);
		EXPECT_EQ(one[i].score, two[i].score);
		EXPECT_TRUE(one[i].pose.t == two[i].pose.t);
	}
	// The default coarse pass agrees with one pass on the best rotation.
	cfg = ViewSearchConfig{};
	ASSERT_GT(searchViews(templates(), cfg, view, K_, voted, two), 0u);
	cfg.coarsePoints = 0;
	ASSERT_GT(searchViews(templates(), cfg, view, K_, voted, one), 0u);
	EXPECT_LT(rotationAngle(one[0].pose.R, two[0].pose.R) * 180.0 / M_PI, 1e-3);
}

// Weighting inliers by their residual (the score's residualWeight) keeps
// finding the rotation of a clean render and separates it further from the
// best distinct wrong rotation, whose points only fall inside the band.
TEST_F(ViewSearchTest, ResidualWeightSeparatesTheTrueRotationFurther)
{
	std::mt19937_64 rng(23);
	ViewSearchConfig plain;
	plain.keep = 2;
	// Without the climb both runs see the same translations and
	// rotations, so the weighted best can only score lower.
	plain.lateralStepMm = 0.0f;
	plain.rotationStepDeg = 0.0f;
	ViewSearchConfig weighted = plain;
	weighted.residualWeight = 1.0f;
	const int trials = 10;
	int found = 0;
	double marginPlain = 0, marginWeighted = 0;
	for (int i = 0; i < trials; ++i) {
		const Pose truth = randomPose(rng);
		const std::vector<float> depth = render(truth);
		ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
		ViewProposal a[2], b[2];
		const Eigen::Vector3d voted = truth.t + Eigen::Vector3d(0, 0, 15);
		ASSERT_EQ(searchViews(templates(), plain, view, K_, voted, a, BoxAxes{false, false, {}}), 2u);
		ASSERT_EQ(searchViews(templates(), weighted, view, K_, voted, b, BoxAxes{false, false, {}}), 2u);
		found += rotationAngle(b[0].pose.R, truth.R) * 180.0 / M_PI < 20;
		// A weight only lowers a score.
		EXPECT_LE(b[0].score, a[0].score + 1e-6f);
		marginPlain += (a[0].score - a[1].score) / a[0].score;
		marginWeighted += (b[0].score - b[1].score) / b[0].score;
	}
	RecordProperty("margin_plain", std::to_string(marginPlain / trials));
	RecordProperty("margin_weighted", std::to_string(marginWeighted / trials));
	EXPECT_GE(found, trials * 3 / 4);
	EXPECT_GT(marginWeighted, marginPlain);
	std::printf("mean relative margin of the best over the next distinct rotation: %.4f plain, %.4f weighted\n",
		    marginPlain / trials, marginWeighted / trials);
}

// Without any voted centre: the box's ray (optical axis) and the median
// depth of the object's pixels place every rotation, and the search finds the
// rotation of a half-occluded object.
TEST_F(ViewSearchTest, DepthAnchorFindsTheRotationWithoutAVotedCentre)
{
	std::mt19937_64 rng(29);
	ViewSearchConfig cfg;
	const int trials = 10;
	int found = 0;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> depth;
		const Pose truth = centredPose(rng, depth);
		std::vector<float> object;
		for (float d : depth)
			if (d < 1100)
				object.push_back(d);
		ASSERT_FALSE(object.empty());
		std::nth_element(object.begin(), object.begin() + object.size() / 2, object.end());
		const float anchor = object[object.size() / 2];
		// An occluder 150 mm in front hides the top third.
		for (int y = 0; y < static_cast<int>(K_.cy) - 15; ++y)
			for (int x = 0; x < K_.width; ++x)
				depth[static_cast<size_t>(y) * K_.width + x] = static_cast<float>(truth.t.z() - 150);
		ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
		found += finds(cfg, view, K_, Eigen::Vector3d::Zero(), truth, 15, {}, anchor);
	}
	RecordProperty("found", found);
	EXPECT_GE(found, trials * 7 / 10);
	// No anchor and no centre: nothing to search at.
	std::vector<float> flat(static_cast<size_t>(K_.width) * K_.height, 800.0f);
	ViewProposal top[2];
	EXPECT_EQ(searchViews(templates(), cfg, ImageView<const float>(flat.data(), K_.width, K_.height, K_.width), K_,
			      Eigen::Vector3d::Zero(), top),
		  0u);
}

// An amodal box round an object half hidden behind an occluder 150 mm in
// front: the box's densest depth is the occluder's. Searched from there,
// the rotations lie on the occluder; placed by the box's size they are
// found where the object is.
TEST_F(ViewSearchTest, PlacedByTheBoxSizeARotationIsFoundBehindAnOccluder)
{
	std::mt19937_64 rng(37);
	ViewSearchConfig cfg;
	const int trials = 6;
	int fromOccluder = 0, bySize = 0;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> depth;
		const Pose truth = centredPose(rng, depth);
		const float occluderMm = static_cast<float>(truth.t.z() - 150);
		const Window window = boxWindow(depth, 1, occluderMm);
		const ImageView<const float> view = window.view();
		const CameraIntrinsics &K = window.K;
		fromOccluder += finds(cfg, view, K, Eigen::Vector3d::Zero(), truth, 20, {}, occluderMm);
		ViewSearchConfig sized = cfg;
		sized.placeBySize = true;
		bySize += finds(sized, view, K, Eigen::Vector3d::Zero(), truth, 20, {}, occluderMm);
	}
	RecordProperty("from_occluder", fromOccluder);
	RecordProperty("by_size", bySize);
	EXPECT_LE(fromOccluder, trials / 3);
	EXPECT_GE(bySize, trials * 2 / 3);
}

// On a depth centre in a box trusted on both axes the coarse pass scores
// each rotation box-centred only (coarseAtCentre false, the default), which
// only changes what reaches the fine pass: keeping every rotation, the
// proposals are exactly those of the coarse pass on both translations.
// Where it does not apply (a voted centre; a box the frame clipped) the two
// settings give the same search whatever is kept.
TEST_F(ViewSearchTest, TheCoarsePassScoresADepthCentreBoxCentredOnly)
{
	std::mt19937_64 rng(31);
	std::vector<float> depth;
	const Pose truth = centredPose(rng, depth);
	ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
	const float anchor = static_cast<float>(truth.t.z() - 10);
	auto same = [](const ViewProposal *a, size_t na, const ViewProposal *b, size_t nb) {
		if (na != nb)
			return false;
		for (size_t i = 0; i < na; ++i)
			if (a[i].view != b[i].view || a[i].turn != b[i].turn || a[i].score != b[i].score ||
			    !(a[i].pose.t == b[i].pose.t))
				return false;
		return true;
	};
	ViewSearchConfig both;
	both.coarseAtCentre = true;
	ViewSearchConfig centred = both;
	centred.coarseAtCentre = false;
	ViewProposal a[6], b[6];
	// Every rotation kept (6 turns: 1920 rotations).
	both.inplane = centred.inplane = 6;
	both.coarseKeep = centred.coarseKeep = kMaxCoarseKeep;
	size_t na = searchViews(templates(), both, view, K_, Eigen::Vector3d::Zero(), a, {}, anchor);
	size_t nb = searchViews(templates(), centred, view, K_, Eigen::Vector3d::Zero(), b, {}, anchor);
	ASSERT_GT(na, 0u);
	EXPECT_TRUE(same(a, na, b, nb));
	EXPECT_TRUE(near(b, nb, truth, 15));
	// The default keep (1024 of 7680): the rotation is still found.
	both = centred = ViewSearchConfig{};
	both.coarseAtCentre = true;
	nb = searchViews(templates(), centred, view, K_, Eigen::Vector3d::Zero(), b, {}, anchor);
	EXPECT_TRUE(near(b, nb, truth, 15));
	// A voted centre, and a depth centre in a box clipped on the left: the
	// same search.
	const Eigen::Vector3d voted = truth.t + Eigen::Vector3d(5, 5, 20);
	na = searchViews(templates(), both, view, K_, voted, a);
	nb = searchViews(templates(), centred, view, K_, voted, b);
	ASSERT_GT(na, 0u);
	EXPECT_TRUE(same(a, na, b, nb));
	BoxAxes clipped{false, true, {}};
	clipped.open.left = true;
	na = searchViews(templates(), both, view, K_, Eigen::Vector3d::Zero(), a, clipped, anchor);
	nb = searchViews(templates(), centred, view, K_, Eigen::Vector3d::Zero(), b, clipped, anchor);
	ASSERT_GT(na, 0u);
	EXPECT_TRUE(same(a, na, b, nb));
}

// A detector's box is off by some percent: its centre, taken for the
// object's, puts the translation millimetres off sideways. The sideways
// climb of the best proposals brings the true rotation back.
TEST_F(ViewSearchTest, LateralClimbUndoesABoxCentreOffByMillimetres)
{
	std::mt19937_64 rng(31);
	ViewSearchConfig plain;
	plain.lateralStepMm = 0.0f;
	plain.rotationStepDeg = 0.0f;
	ViewSearchConfig climbing = plain;
	climbing.lateralStepMm = 4.0f;
	const int trials = 10;
	int found = 0, foundPlain = 0;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> depth;
		Pose truth = centredPose(rng, depth);
		// The box's centre is 9 mm off the object's extent's.
		truth.t += Eigen::Vector3d(i % 2 ? 9.0 : -9.0, i % 3 ? 6.0 : -6.0, 0);
		depth = render(truth);
		ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
		const Eigen::Vector3d voted(0, 0, truth.t.z() + 10);
		ViewProposal top[6];
		found += finds(climbing, view, K_, voted, truth, 6);
		foundPlain += finds(plain, view, K_, voted, truth, 6);
		// Proposals stay best first.
		const size_t n = searchViews(templates(), climbing, view, K_, voted, top);
		for (size_t j = 1; j < n; ++j)
			EXPECT_GE(top[j - 1].score, top[j].score);
	}
	RecordProperty("found", found);
	RecordProperty("found_plain", foundPlain);
	EXPECT_GE(found, trials * 6 / 10); // measured 7 of 10, 3 without the climb

	EXPECT_GT(found, foundPlain + 2);
}

// A box further off centre: a fifth of the object's extent on either axis,
// with the object's left third behind an occluder. The box's centre puts
// the true rotation tens of millimetres off, where wrong rotations outscore
// it before the climb; the placements shifted to either side of the centre
// (centreShiftShare) find it more often. (On clean renders a tenth is
// mostly undone by the climb alone, 11 of 12 against 12; on the noisy,
// occluded benchmarks it is not, BENCHMARKS.md.)
TEST_F(ViewSearchTest, ShiftedPlacementsFindTheObjectOffTheBoxCentre)
{
	std::mt19937_64 rng(37);
	ViewSearchConfig shifted; // the default shifts
	ViewSearchConfig centred = shifted;
	centred.centreShiftShare = 0.0f;
	// The coarse pass trying the shifts on the best rotations only.
	ViewSearchConfig best = shifted;
	best.coarseShifted = 2;
	const int trials = 12;
	int found = 0, foundCentred = 0, foundBest = 0;
	for (int i = 0; i < trials; ++i) {
		std::vector<float> depth;
		Pose truth = centredPose(rng, depth);
		const auto [u0, u1, v0, v1] = extent(depth);
		const double dx = 0.2 * (u1 - u0) * truth.t.z() / K_.fx, dy = 0.2 * (v1 - v0) * truth.t.z() / K_.fy;
		truth.t += Eigen::Vector3d(i % 2 ? dx : -dx, i % 3 ? dy : -dy, 0);
		depth = render(truth);
		const Extent e = extent(depth);
		const float occluderMm = static_cast<float>(truth.t.z() - 120);
		for (int y = 0; y < K_.height; ++y)
			for (int x = 0; x < e.u0 + (e.u1 - e.u0) / 3; ++x)
				depth[static_cast<size_t>(y) * K_.width + x] = occluderMm;
		ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
		const Eigen::Vector3d voted(0, 0, truth.t.z() + 10);
		found += finds(shifted, view, K_, voted, truth, 8);
		foundCentred += finds(centred, view, K_, voted, truth, 8);
		foundBest += finds(best, view, K_, voted, truth, 8);
	}
	RecordProperty("found", found);
	RecordProperty("found_centred", foundCentred);
	RecordProperty("found_best_shifted", foundBest);
	// 4 of 12 measured, 4 with the shifts on the best rotations only, 1
	// centred only.
	EXPECT_GE(found, trials / 3);
	EXPECT_GT(found, foundCentred + 2);
	EXPECT_GE(foundBest, found - 1);
	EXPECT_GT(foundBest, foundCentred + 1);
}

// Shifted placements tried on at least as many rotations as there are give
// the same proposals as tried on all of them.
TEST_F(ViewSearchTest, ShiftedPlacementsOnTheBestRotationsCoveringAllEqualAll)
{
	std::mt19937_64 rng(41);
	std::vector<float> depth;
	const Pose truth = centredPose(rng, depth);
	ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
	ViewSearchConfig all;
	all.inplane = 6; // 1920 rotations
	ViewSearchConfig covering = all;
	covering.coarseShifted = 2; // the best 2048
	ViewSearchConfig few = all;
	few.coarseKeep = 64;
	few.coarseShifted = 1; // the best 64 only
	const Eigen::Vector3d voted(0, 0, truth.t.z() + 10);
	ViewProposal a[6], b[6], c[6];
	const size_t na = searchViews(templates(), all, view, K_, voted, a);
	const size_t nb = searchViews(templates(), covering, view, K_, voted, b);
	ASSERT_GT(na, 0u);
	ASSERT_EQ(na, nb);
	for (size_t i = 0; i < na; ++i) {
		EXPECT_EQ(a[i].view, b[i].view);
		EXPECT_EQ(a[i].turn, b[i].turn);
		EXPECT_EQ(a[i].score, b[i].score);
		EXPECT_TRUE(a[i].pose.t == b[i].pose.t);
	}
	// Fewer: the same centred truth still found.
	const size_t nc = searchViews(templates(), few, view, K_, voted, c);
	EXPECT_TRUE(near(c, nc, truth, 8));
}

// The template grid's rotations are up to ~10 deg from a pose. The climb's
// turns bring the best proposals' rotations closer to the truth (and they
// must reach the proposals' poses).
TEST_F(ViewSearchTest, TurningClimbBringsRotationsCloserThanTheGrid)
{
	std::mt19937_64 rng(47);
	ViewSearchConfig sideways;
	sideways.rotationStepDeg = 0.0f;
	ViewSearchConfig turning = sideways;
	turning.rotationStepDeg = 8.0f;
	const int trials = 10;
	double errTurning = 0, errSideways = 0;
	int both = 0;
	auto closest = [](const ViewProposal *top, size_t n, const Pose &truth) {
		double best = 180;
		for (size_t j = 0; j < n; ++j)
			if ((top[j].pose.t - truth.t).norm() < 15)
				best = std::min(best, rotationAngle(top[j].pose.R, truth.R) * 180.0 / M_PI);
		return best;
	};
	for (int i = 0; i < trials; ++i) {
		std::vector<float> depth;
		const Pose truth = centredPose(rng, depth);
		ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
		const Eigen::Vector3d voted(0, 0, truth.t.z() + 10);
		ViewProposal top[6];
		const double a = closest(top, searchViews(templates(), turning, view, K_, voted, top), truth);
		const size_t n = searchViews(templates(), turning, view, K_, voted, top);
		for (size_t j = 1; j < n; ++j)
			EXPECT_GE(top[j - 1].score, top[j].score);
		const double b = closest(top, searchViews(templates(), sideways, view, K_, voted, top), truth);
		if (a < 20 && b < 20) {
			errTurning += a;
			errSideways += b;
			++both;
		}
	}
	ASSERT_GE(both, trials * 6 / 10);
	RecordProperty("mean_deg_turning", std::to_string(errTurning / both));
	RecordProperty("mean_deg_sideways", std::to_string(errSideways / both));
	EXPECT_LT(errTurning, 0.8 * errSideways); // measured 5.7 against 8.7 deg
}

// A climb that turns the pose towards another view scores it on that view's
// points: otherwise it drifts tens of degrees scoring points the pose hides,
// and finds the poses that lay those on whatever they fit (an occluder, the
// wall). Half-hidden objects, searched at a voted centre and placed by the
// box's size in the box's window: each proposal's view direction is as near
// its own view as the nearest view's (up to its offset off the optical
// axis, which the search's placements make).
TEST_F(ViewSearchTest, ClimbedProposalsAreScoredOnTheViewTheyShow)
{
	std::mt19937_64 rng(53);
	const ViewTemplates views = templates();
	auto direction = [&](int v) { return fibonacciDirection(v, views.viewpoints); };
	double worst = 0;
	int proposals = 0;
	for (int i = 0; i < 6; ++i) {
		std::vector<float> depth;
		const Pose truth = centredPose(rng, depth);
		const float occluderMm = static_cast<float>(truth.t.z() - 120);
		const Window window = boxWindow(depth, 1, occluderMm);
		const ImageView<const float> view = window.view();
		const CameraIntrinsics &K = window.K;
		const BoxAxes box{true, true, {}};
		for (const bool bySize : {false, true}) {
			ViewSearchConfig cfg;
			cfg.placeBySize = bySize;
			const Eigen::Vector3d voted(0, 0, truth.t.z() + 10);
			ViewProposal top[6];
			const size_t n = searchViews(views, cfg, view, K, bySize ? Eigen::Vector3d::Zero() : voted, top,
						     box, bySize ? occluderMm : 0.0f);
			ASSERT_GT(n, 0u) << i << " " << bySize;
			for (size_t j = 0; j < n; ++j) {
				const Pose &p = top[j].pose;
				const Eigen::Vector3d seen = -(p.R.transpose() * p.t.normalized());
				auto off = [&](int v) { return std::acos(std::clamp(seen.dot(direction(v)), -1.0, 1.0)); };
				const double aside = std::atan2(p.t.head<2>().norm(), p.t.z());
				const double past = off(top[j].view) - off(nearestView(views, p));
				worst = std::max(worst, past * 180.0 / M_PI);
				EXPECT_LE(past, aside + 1e-6) << i << " " << bySize << " " << j;
				++proposals;
			}
		}
	}
	RecordProperty("proposals", proposals);
	RecordProperty("worst_deg_past_nearest", std::to_string(worst));
}

// A template's own rotation, on its view's ray or off it by the lateral
// offsets of a crop, is nearest that view; the tabled directions (the
// model's) pick as the computed ones do.
TEST_F(ViewSearchTest, NearestViewOfATemplatesRotationIsItsView)
{
	ViewTemplates t = templates();
	EXPECT_EQ(nearestView(ViewTemplates{}, Pose{}), -1);
	std::vector<Eigen::Vector3f> dirs;
	for (int v = 0; v < t.viewpoints; ++v)
		dirs.push_back(fibonacciDirection(v, t.viewpoints).cast<float>());
	ViewTemplates tabled = t;
	tabled.directions = dirs;
	int offRay = 0, checked = 0;
	for (int v = 0; v < t.viewpoints; v += 29)
		for (int turn : {0, 5, 17}) {
			Pose p;
			p.R = viewRotation(t, 24, v, turn);
			p.t = Eigen::Vector3d(0, 0, 800);
			EXPECT_EQ(nearestView(t, p), v) << v << " " << turn;
			EXPECT_EQ(nearestView(tabled, p), v) << v << " " << turn;
			// 60 mm aside at 800 mm: the ray turns by ~4 deg, less than
			// the lattice's spacing (~11 deg), so the view is the same or
			// a neighbour.
			p.t = Eigen::Vector3d(60, -40, 800);
			const int w = nearestView(tabled, p);
			EXPECT_EQ(w, nearestView(t, p));
			ASSERT_GE(w, 0);
			const double apart = std::acos(std::clamp(
				fibonacciDirection(v, t.viewpoints).dot(fibonacciDirection(w, t.viewpoints)), -1.0, 1.0));
			EXPECT_LT(apart * 180.0 / M_PI, 15.0) << v;
			offRay += w != v;
			++checked;
		}
	EXPECT_LT(offRay, checked);
	Pose behind;
	behind.t = Eigen::Vector3d(0, 0, -500);
	EXPECT_EQ(nearestView(tabled, behind), -1);
}

// The sparse score of any pose (the half-turns' screen): high at the truth
// of a clean render, where it also finds the depth of a pose 25 mm off; a
// half-turn of the truth, also on the same spot, scores lower in most views.
TEST_F(ViewSearchTest, SparsePoseScoreFindsTheDepthAndTellsTheTruthFromItsHalfTurn)
{
	std::mt19937_64 rng(11);
	ViewSearchConfig cfg;
	const ViewTemplates t = templates();
	const Eigen::Vector3d centre = boundingBox(*mesh_).centre().cast<double>();
	int lower = 0;
	const int trials = 12;
	for (int i = 0; i < trials; ++i) {
		const Pose truth = randomPose(rng);
		const std::vector<float> depth = render(truth);
		const ImageView<const float> obs(depth.data(), K_.width, K_.height, K_.width);
		Eigen::Vector3d aligned;
		const float atTruth = sparsePoseScore(t, nearestView(t, truth), cfg, obs, K_, truth, BoxAxes{}, aligned);
		EXPECT_GT(atTruth, 0.85f) << i;
		EXPECT_LT((aligned - truth.t).norm(), 2.0) << i;
		Pose off = truth;
		off.t *= 1.0 + 25.0 / truth.t.norm();
		const float atOff = sparsePoseScore(t, nearestView(t, off), cfg, obs, K_, off, BoxAxes{}, aligned);
		EXPECT_GT(atOff, 0.8f) << i;
		EXPECT_LT((aligned - truth.t).norm(), 4.0) << i;
		// Turned about the camera's x axis through the model's centre.
		const Eigen::Matrix3d flipModel = truth.R.transpose() * Eigen::Matrix3d(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())) * truth.R;
		const Pose turned = turnedAbout(truth, flipModel, centre);
		const float atTurn = sparsePoseScore(t, nearestView(t, turned), cfg, obs, K_, turned, BoxAxes{}, aligned);
		lower += atTurn < atTruth - 0.1f;
	}
	EXPECT_GE(lower, trials * 3 / 4);
	Eigen::Vector3d aligned;
	EXPECT_EQ(sparsePoseScore(t, -1, cfg, ImageView<const float>(), K_, Pose{}, BoxAxes{}, aligned), 0.0f);
}

// The sparse score agrees with the box as the full score does: the truth in
// the window of a box drawn round it scores the same with the agreement on
// (it fills the box), and in a window three times as wide and high (a box
// round something else, the object a ninth of it) the agreement takes it
// to (fill / boxMinFill)^boxWeight of that; off, the wide window changes
// nothing.
TEST_F(ViewSearchTest, SparseScoreAgreesWithTheBoxAsTheFullScoreDoes)
{
	std::mt19937_64 rng(19);
	const ViewTemplates t = templates();
	ViewSearchConfig off;
	ViewSearchConfig on = off;
	on.boxWeight = 1.5f;
	for (int i = 0; i < 4; ++i) {
		std::vector<float> depth;
		const Pose truth = centredPose(rng, depth);
		auto score = [&](const ViewSearchConfig &cfg, int scale) {
			const Window window = boxWindow(depth, scale);
			Eigen::Vector3d aligned;
			return sparsePoseScore(t, nearestView(t, truth), cfg, window.view(), window.K, truth, BoxAxes{},
					       aligned);
		};
		const float tight = score(off, 1);
		EXPECT_GT(tight, 0.8f) << i;
		EXPECT_FLOAT_EQ(score(on, 1), tight) << i;
		EXPECT_FLOAT_EQ(score(off, 3), tight) << i;
		// The points' extent is a little inside the object's: a ninth of
		// the window at most.
		const float wide = score(on, 3);
		EXPECT_LT(wide, tight * std::pow(1.0f / 9.0f / on.boxMinFill, on.boxWeight) * 1.01f) << i;
		EXPECT_GT(wide, 0.0f) << i;
	}
}

TEST_F(ViewSearchTest, OffWithoutTurnsOrTemplates)
{
	ViewSearchConfig cfg;
	cfg.inplane = 0; // off
	std::vector<float> depth(static_cast<size_t>(K_.width) * K_.height, 800.0f);
	ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
	ViewProposal top[4];
	EXPECT_EQ(viewSearchSize(templates(), cfg), 0);
	EXPECT_EQ(searchViews(templates(), cfg, view, K_, Eigen::Vector3d(0, 0, 800), top), 0u);
	cfg.inplane = 12;
	EXPECT_EQ(viewSearchSize(ViewTemplates{}, cfg), 0);
	EXPECT_EQ(searchViews(ViewTemplates{}, cfg, view, K_, Eigen::Vector3d(0, 0, 800), top), 0u);
	// A centre behind the camera has no view.
	EXPECT_EQ(searchViews(templates(), cfg, view, K_, Eigen::Vector3d(0, 0, -5), top), 0u);
}

TEST(ViewTemplateBuilder, RejectsAnEmptyMeshAndBadCounts)
{
	Mesh empty;
	auto r = buildViewTemplatePoints(empty, 100.0, {});
	ASSERT_FALSE(r);
	EXPECT_NE(std::string(r.error().message).find("empty mesh"), std::string::npos);
	Mesh tri;
	tri.vertices = {{0, 0, 0}, {50, 0, 0}, {0, 50, 0}};
	tri.faces = {{0, 1, 2}};
	auto bad = buildViewTemplatePoints(tri, 70.0, {0, 64});
	ASSERT_FALSE(bad);
	EXPECT_NE(std::string(bad.error().message).find("positive"), std::string::npos);
}

// A pool spreads the coarse pass, the fine pass and the sideways climb over
// its threads; the proposals are the same bits as with one thread, for
// voted and anchored centres, with and without the box's centring.
TEST_F(ViewSearchTest, ThreadsGiveTheSameProposals)
{
	std::mt19937_64 rng(23);
	for (int trial = 0; trial < 3; ++trial) {
		const Pose truth = randomPose(rng);
		const std::vector<float> depth = render(truth);
		ImageView<const float> view(depth.data(), K_.width, K_.height, K_.width);
		ViewSearchConfig cfg;
		cfg.inplane = 12;
		cfg.coarseKeep = 300;
		cfg.coarseShifted = trial == 0 ? 0 : 2; // the shifts on all rotations, on the best only
		const Eigen::Vector3d voted = truth.t + Eigen::Vector3d(4, -6, 25);
		const float anchor = trial == 2 ? static_cast<float>(truth.t.z()) : 0.0f;
		const BoxAxes axes = trial == 1 ? BoxAxes{false, false, {}} : BoxAxes{};
		ViewProposal one[6];
		const size_t n1 = searchViews(templates(), cfg, view, K_, voted, one, axes, anchor);
		ASSERT_GT(n1, 0u);
		for (int threads : {2, 3}) {
			WorkerPool pool(threads);
			std::vector<ViewCoarseCandidate> heaps(viewSearchHeapSize(threads));
			std::vector<ViewFineResult> fine(kMaxCoarseKeep);
			ViewProposal many[6];
			const size_t n = searchViews(templates(), cfg, view, K_, voted, many, axes, anchor, &pool,
						     ViewSearchWorkspace{heaps, fine});
			ASSERT_EQ(n, n1) << "trial " << trial << ", " << threads << " threads";
			for (size_t i = 0; i < n; ++i) {
				EXPECT_EQ(many[i].view, one[i].view) << "trial " << trial << ", proposal " << i;
				EXPECT_EQ(many[i].turn, one[i].turn);
				EXPECT_EQ(many[i].score, one[i].score);
				EXPECT_TRUE(many[i].pose.t == one[i].pose.t);
			}
		}
	}
}

} // namespace
} // namespace ihf

// Under a frame budget the climb and the coarse pass fall back to their
// budget settings; the rest of the search is unchanged.
TEST(ViewSearch, UnderBudgetTakesTheBudgetClimbAndCoarsePass)
{
	ihf::ViewSearchConfig c;
	c.rotationStepDeg = 8.0f;
	c.refineTop = 64;
	c.coarsePoints = 32;
	c.coarseKeep = 1024;
	c.budgetRotationStepDeg = 2.0f;
	c.budgetRefineTop = 24;
	c.budgetCoarsePoints = 12;
	c.budgetCoarseKeep = 100;
	c.budgetCoarseShifted = 3;
	c.depthCentres = 3;
	c.budgetDepthCentres = 2;
	c.depthCentreWidth = 0.5f;
	c.budgetDepthCentreWidth = 0.0f;
	c.lateralStepMm = 3.0f;
	c.depthFirst = false;
	c.budgetDepthFirst = true;
	c.centreShiftShare = 0.06f;
	c.budgetCentreShiftShare = 0.0f;
	const ihf::ViewSearchConfig b = ihf::underBudget(c);
	EXPECT_EQ(b.centreShiftShare, 0.0f);
	EXPECT_EQ(b.rotationStepDeg, 2.0f);
	EXPECT_EQ(b.refineTop, 24);
	EXPECT_EQ(b.coarsePoints, 12);
	EXPECT_EQ(b.coarseKeep, 100);
	EXPECT_EQ(b.coarseShifted, 3);
	EXPECT_EQ(b.depthCentres, 2);
	EXPECT_EQ(b.depthCentreWidth, 0.0f);
	EXPECT_TRUE(b.depthFirst);
	EXPECT_EQ(b.lateralStepMm, 3.0f);
	EXPECT_EQ(b.keep, c.keep);
	EXPECT_EQ(b.inplane, c.inplane);
	// A share of few searches: the lean climb and coarse pass, the rest the
	// budget's.
	c.leanRotationStepDeg = 0.0f;
	c.leanCoarsePoints = 8;
	const ihf::ViewSearchConfig l = ihf::underLeanBudget(c);
	EXPECT_EQ(l.rotationStepDeg, 0.0f);
	EXPECT_EQ(l.coarsePoints, 8);
	EXPECT_EQ(l.refineTop, 24);
	EXPECT_EQ(l.coarseKeep, 100);
	EXPECT_EQ(l.depthCentres, 2);
	EXPECT_TRUE(l.depthFirst);
	c.refineTop = 10; // never more climbers or centres than unbudgeted
	EXPECT_EQ(ihf::underBudget(c).refineTop, 10);
	c.depthCentres = 1;
	EXPECT_EQ(ihf::underBudget(c).depthCentres, 1);
}
