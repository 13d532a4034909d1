// SPDX-License-Identifier: MIT
// The polish's projective point-to-plane ICP: from a pose a few millimetres
// and degrees off, on a clean render of the LM-O duck, it comes back to the
// truth, whether it renders every iteration or once and associates through
// the pose change since; with one render a far start is not made worse.

#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/icp_refiner.h"
#include "core/features/depth_cloud.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/pose.h"
#include "core/render/depth_renderer.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

constexpr double kDeg = M_PI / 180.0;

class IcpOnADuck : public ::testing::Test
{
protected:
	void SetUp() override
	{
		auto loaded = loadPly(test::lmoDir() / "models" / "obj_000009.ply");
		ASSERT_TRUE(loaded) << loaded.error().message;
		mesh = std::move(*loaded);
		truth.R = (Eigen::AngleAxisd(-70 * kDeg, Eigen::Vector3d::UnitX()) *
			   Eigen::AngleAxisd(40 * kDeg, Eigen::Vector3d::UnitZ())).toRotationMatrix();
		truth.t = Eigen::Vector3d(10, -5, 800);
		renderer = std::make_unique<DepthRenderer>(mesh.vertices.size());
		scene.assign(static_cast<size_t>(K.width) * K.height, 0.0f);
		scratch.assign(scene.size(), 0.0f);
		ASSERT_TRUE(renderer->render(mesh, truth, K, ImageView<float>(scene.data(), K.width, K.height, K.width)));
		cloud.resize(scene.size());
		auto n = cloudFromDepth(ImageView<const float>(scene.data(), K.width, K.height, K.width), K,
					PixelBox{0, 0, K.width, K.height}, DepthCloudConfig{}, cloud);
		ASSERT_TRUE(n);
		ASSERT_GT(*n, 500);
		cloud.resize(static_cast<size_t>(*n));
	}
	IcpResult refine(const Pose &start, const IcpConfig &cfg)
	{
		return refineIcp(cloud, mesh, start, K, *renderer,
				 ImageView<float>(scratch.data(), K.width, K.height, K.width), cfg);
	}
	Pose offBy(double mm, double deg) const
	{
		Pose p = truth;
		p.R = Eigen::AngleAxisd(deg * kDeg, Eigen::Vector3d(1, -2, 1).normalized()).toRotationMatrix() * p.R;
		p.t += mm * Eigen::Vector3d(2, 1, -2).normalized();
		return p;
	}

	const CameraIntrinsics K{572.4114, 573.57043, 160.0, 120.0, 320, 240};
	Mesh mesh;
	Pose truth;
	std::unique_ptr<DepthRenderer> renderer;
	std::vector<float> scene, scratch;
	std::vector<CloudPoint> cloud;
};

TEST_F(IcpOnADuck, ComesBackToTheTruthRenderingEveryIterationOrOnce)
{
	const Pose start = offBy(6.0, 4.0);
	for (bool once : {false, true}) {
		IcpConfig cfg;
		cfg.iterations = 10;
		cfg.renderOnce = once;
		const IcpResult r = refine(start, cfg);
		EXPECT_GT(r.iterations, 1) << once;
		EXPECT_GT(r.correspondences, 500) << once;
		EXPECT_LT((r.pose.t - truth.t).norm(), 1.0) << once;
		EXPECT_LT(rotationAngle(r.pose.R, truth.R), 0.5 * kDeg) << once;
		EXPECT_LT(r.rmsMm, 0.5f) << once;
	}
}

// One render, associated through the pose change: the start's association
// at the first iteration is the same as rendering (identity change), so a
// single iteration gives the same pose either way.
TEST_F(IcpOnADuck, OneIterationIsTheSameEitherWay)
{
	const Pose start = offBy(4.0, 3.0);
	IcpConfig cfg;
	cfg.iterations = 1;
	const IcpResult every = refine(start, cfg);
	cfg.renderOnce = true;
	const IcpResult once = refine(start, cfg);
	EXPECT_TRUE(once.pose.R.isApprox(every.pose.R, 1e-12));
	EXPECT_TRUE(once.pose.t.isApprox(every.pose.t, 1e-12));
	EXPECT_EQ(once.correspondences, every.correspondences);
}

// With one render the later iterations still move towards the truth: the
// second iteration's association is through the pose change, not the
// start's pixels again (else it would repeat the first step's solution).
TEST_F(IcpOnADuck, LaterIterationsAssociateThroughThePoseChange)
{
	const Pose start = offBy(6.0, 4.0);
	IcpConfig cfg;
	cfg.renderOnce = true;
	cfg.iterations = 1;
	const IcpResult first = refine(start, cfg);
	cfg.iterations = 3;
	const IcpResult third = refine(start, cfg);
	const double firstError = (first.pose.t - truth.t).norm();
	EXPECT_LT((third.pose.t - truth.t).norm(), 0.5 * firstError);
}

} // namespace
} // namespace ihf
