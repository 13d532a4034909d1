// SPDX-License-Identifier: MIT
// VisibleSurfaceScorer (BOP's e_VSD) on the procedural cup seen from the
// side: the truth scores 0, a pose beside it 1, and a turn that moves the
// handle costs only where the depth shows where the handle is.

#include <numbers>

#include <gtest/gtest.h>

#include "core/eval/pose_error.h"
#include "core/eval/visible_surface.h"
#include "core/render/depth_renderer.h"
#include "core/synth/household_objects.h"
#include "tests/common/part_pixels.h"

namespace ihf {
namespace {

// 0.05 .. 0.50 of the cup's size, about 120 mm across.
std::vector<double> tausMm()
{
	std::vector<double> taus;
	for (double share : vsdTauShares())
		taus.push_back(share * 120.0);
	return taus;
}

// Looking at the cup from the side (camera -y of it), the handle (+x)
// on the right.
Pose sideView()
{
	Pose p;
	p.R = Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
	p.t = {0, -47, 600}; // the cup's middle (z = 47) on the optical axis
	return p;
}

// The same pose turned half round the cup's own axis: the handle on the left.
Pose handleTurned(const Pose &pose)
{
	Pose p = pose;
	p.R = pose.R * Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	return p;
}

DepthImageMm render(const Mesh &mesh, const Pose &pose)
{
	const CameraIntrinsics K = kinectV1Intrinsics();
	DepthImageMm depth(K.width, K.height, 0.0f);
	DepthRenderer renderer(mesh.vertices.size());
	EXPECT_TRUE(renderer.render(mesh, pose, K, depth.view()).ok());
	return depth;
}

class VisibleSurface : public ::testing::Test
{
protected:
	Mesh cup_ = makeCup();
	Mesh body_ = makeCup(false);
	VisibleSurfaceScorer scorer_{cup_};

	std::vector<double> errors(const Pose &est, const Pose &gt, const DepthImageMm &test)
	{
		auto e = scorer_.errors(est, gt, test.view(), kinectV1Intrinsics(), tausMm());
		EXPECT_TRUE(e.ok()) << e.error().message;
		return e.ok() ? *e : std::vector<double>(tausMm().size(), -1.0);
	}

	// The truth's render with a wall 300 mm in front of the camera over
	// every pixel where either pose draws its handle: the handles hidden,
	// the bodies in view.
	DepthImageMm handlesHidden(const Pose &a, const Pose &b)
	{
		DepthImageMm test = render(cup_, a);
		for (const Pose *pose : {&a, &b}) {
			auto handle = test::partPixels(cup_, body_, *pose, kinectV1Intrinsics());
			EXPECT_TRUE(handle.ok()) << handle.error().message;
			if (!handle)
				continue;
			for (int y = 0; y < test.height(); ++y)
				for (int x = 0; x < test.width(); ++x)
					if (handle->at(x, y))
						test.at(x, y) = 300.0f;
		}
		return test;
	}
};

TEST_F(VisibleSurface, TheTruthScoresZero)
{
	const DepthImageMm test = render(cup_, sideView());
	for (double e : errors(sideView(), sideView(), test))
		EXPECT_EQ(e, 0.0);
}

TEST_F(VisibleSurface, APoseBesideTheTruthScoresOne)
{
	const DepthImageMm test = render(cup_, sideView());
	Pose beside = sideView();
	beside.t.x() += 300;
	for (double e : errors(beside, sideView(), test))
		EXPECT_EQ(e, 1.0);
}

TEST_F(VisibleSurface, AHandleTurnedAwayInViewIsWrong)
{
	const Pose truth = sideView(), turned = handleTurned(truth);
	const DepthImageMm test = render(cup_, truth);
	// The handle is a small share of the silhouette, yet no tau forgives it.
	for (double e : errors(turned, truth, test)) {
		EXPECT_GT(e, vsdThetas().front());
		EXPECT_LT(e, 0.5);
	}
}

TEST_F(VisibleSurface, AHandleTurnedWhereNoDepthShowsItCostsNothing)
{
	const Pose truth = sideView(), turned = handleTurned(truth);
	const DepthImageMm test = handlesHidden(truth, turned);
	for (double e : errors(turned, truth, test))
		EXPECT_LT(e, vsdThetas().front());
	// ADD counts the same turn far off: every point has turned half round.
	EXPECT_GT(addError(turned, truth, cup_.vertices), 0.1 * 120.0);
}

TEST_F(VisibleSurface, NoDepthWhereTheObjectIsDrawnCountsAsSeen)
{
	// A sensor with no data at all: both renders are visible everywhere,
	// so the turned handle shows as it does with nothing in front of it.
	const Pose truth = sideView(), turned = handleTurned(truth);
	const DepthImageMm none(kinectV1Intrinsics().width, kinectV1Intrinsics().height, 0.0f);
	const std::vector<double> blind = errors(turned, truth, none);
	const std::vector<double> seen = errors(turned, truth, render(cup_, truth));
	ASSERT_EQ(blind.size(), seen.size());
	for (size_t i = 0; i < blind.size(); ++i)
		EXPECT_NEAR(blind[i], seen[i], 1e-9);
}

TEST_F(VisibleSurface, NoCameraIsAnError)
{
	const DepthImageMm test = render(cup_, sideView());
	auto e = scorer_.errors(sideView(), sideView(), test.view(), CameraIntrinsics{}, tausMm());
	ASSERT_FALSE(e.ok());
	EXPECT_EQ(e.error().code, Errc::kInvalidArgument);
}

} // namespace
} // namespace ihf
