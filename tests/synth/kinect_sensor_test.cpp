// SPDX-License-Identifier: MIT
// The Kinect v1 model: noise statistics against Nguyen et al.'s formula,
// disparity quantisation, projector shadows on the expected side, range
// limits, grazing-angle dropout and determinism.

#include <cmath>
#include <map>
#include <numbers>

#include <gtest/gtest.h>

#include "core/synth/kinect_sensor.h"
#include "core/synth/primitive_mesh.h"
#include "core/synth/projector_shadow.h"
#include "core/synth/scene_render.h"
#include "core/synth/synth_config.h"
#include "tests/synth/tilted_plane.h"

namespace ihf {
namespace {

// Parameters with every dropout switched off, to look at one effect.
KinectParams quietParams()
{
	KinectParams p;
	p.edgeDropout = 0;
	p.blobsPerImage = 0;
	p.pixelDropout = 0;
	p.leftBandMin = p.leftBandMax = 0;
	return p;
}

struct Stats {
	double mean = 0, sd = 0;
	int n = 0;
};

Stats planeStats(double zMm, const KinectParams &p, uint64_t seed)
{
	const CameraIntrinsics K = kinectV1Intrinsics();
	DepthImageMm plane(K.width, K.height, static_cast<float>(zMm));
	// The projector sees the same fronto-parallel plane: no shadow.
	const int pad = projectorPadding(K, p.baselineMm, 400);
	DepthImageMm proj(K.width + pad, K.height, static_cast<float>(zMm));
	SensorScene scene;
	scene.depth = plane.view();
	scene.projector = proj.view();
	scene.projectorX0 = -pad;
	SynthRandom rng(seed);
	const DepthImage16 out = simulateKinect(scene, K, p, rng);
	Stats s;
	double sum = 0, sum2 = 0;
	for (uint16_t v : out.pixels()) {
		if (v == 0)
			continue;
		sum += v;
		sum2 += static_cast<double>(v) * v;
		++s.n;
	}
	s.mean = sum / s.n;
	s.sd = std::sqrt(sum2 / s.n - s.mean * s.mean);
	return s;
}

TEST(KinectSensor, AxialSigmaFollowsNguyen2012)
{
	const KinectParams p;
	// 0.0012 + 0.0019 (z - 0.4)^2 metres.
	EXPECT_NEAR(kinectAxialSigmaMm(p, 1000, 0.3), 1.2 + 1.9 * 0.36, 1e-9);
	EXPECT_NEAR(kinectAxialSigmaMm(p, 2000, 0.3), 1.2 + 1.9 * 2.56, 1e-9);
	// Grazing term beyond 60 degrees: + 0.1 mm / sqrt(z) theta^2 / (pi/2 - theta)^2.
	const double t = 70 * std::numbers::pi / 180;
	const double r = t / (std::numbers::pi / 2 - t);
	EXPECT_NEAR(kinectAxialSigmaMm(p, 1000, t), 1.2 + 1.9 * 0.36 + 0.1 * r * r, 1e-9);
}

TEST(KinectSensor, DisparityQuantisationSteps)
{
	const KinectParams p;
	// b f / z in 1/8 px: at 1 m, 75 * 580 / 1000 = 43.5 px = 348/8 exactly.
	EXPECT_NEAR(kinectQuantise(p, 1000.0), 1000.0, 1e-9);
	EXPECT_NEAR(kinectDepthStep(p, 1000.0), 1e6 / (75.0 * 580.0 * 8.0), 1e-9);
	// Values snap to b f / (k / 8).
	const double q = kinectQuantise(p, 1001.2);
	const double k = 75.0 * 580.0 * 8.0 / q;
	EXPECT_NEAR(k, std::round(k), 1e-9);
	EXPECT_NEAR(kinectQuantise(p, 2000.0) - kinectQuantise(p, 2000.0 + 0.6 * kinectDepthStep(p, 2000.0)),
		    -kinectDepthStep(p, 2000.0), 0.2);
}

TEST(KinectSensor, FlatPlaneNoiseMatchesTheModel)
{
	const KinectParams p = quietParams();
	for (double z : {1000.0, 2000.0}) {
		const Stats s = planeStats(z, p, 11);
		const double model = kinectAxialSigmaMm(p, z, 0.0);
		SCOPED_TRACE(z);
		EXPECT_GT(s.n, 640 * 480 * 9 / 10);
		EXPECT_NEAR(s.mean, z, 0.1 * model);
		EXPECT_NEAR(s.sd, model, 0.12 * model);
	}
}

TEST(KinectSensor, FlatPlaneValuesLieOnTheDisparityGrid)
{
	const KinectParams p = quietParams();
	const CameraIntrinsics K = kinectV1Intrinsics();
	DepthImageMm plane(K.width, K.height, 1500.0f);
	SensorScene scene;
	scene.depth = plane.view();
	SynthRandom rng(5);
	const DepthImage16 out = simulateKinect(scene, K, p, rng);
	std::map<int, int> values;
	for (uint16_t v : out.pixels())
		if (v)
			++values[v];
	// Steps of ~6.5 mm at 1.5 m: within +-4 sigma (~13 mm) only a handful
	// of distinct values occur, each on the grid up to the mm rounding.
	EXPECT_LE(values.size(), 12u);
	for (const auto &[v, n] : values) {
		const double k = 75.0 * 580.0 * 8.0 / v;
		const double back = 75.0 * 580.0 * 8.0 / std::round(k);
		EXPECT_LE(std::abs(back - v), 0.5 + 1e-9) << v;
	}
}

TEST(KinectSensor, RangeLimits)
{
	const KinectParams p = quietParams();
	for (double z : {350.0, 4600.0}) {
		const Stats s = planeStats(z, p, 2);
		EXPECT_EQ(s.n, 0) << z;
	}
}

// A 100 mm box standing 300 mm in front of a wall at 1 m, both fronto-parallel.
struct ShadowScene {
	CameraIntrinsics K = kinectV1Intrinsics();
	SceneLayout layout;
	DepthImageMm depth{K.width, K.height};
	Image<uint16_t> label{K.width, K.height};
	int pad = 0;
	DepthImageMm proj;

	explicit ShadowScene(const KinectParams &p)
	{
		SceneObject wall, box;
		wall.role = SceneRole::kRoom;
		wall.mesh = std::make_shared<const Mesh>(makeQuad(4000, 4000));
		wall.modelToWorld.R = Eigen::Vector3d(1, -1, -1).asDiagonal(); // faces the camera
		wall.modelToWorld.t = {0, 0, 1000};
		box.role = SceneRole::kTarget;
		box.mesh = std::make_shared<const Mesh>(makeBox(100, 100, 100));
		box.modelToWorld.R = Eigen::Vector3d(1, -1, -1).asDiagonal();
		box.modelToWorld.t = {0, 0, 800}; // front face at 700 mm
		layout.objects = {box, wall};
		SceneRenderer r(K, 1000);
		EXPECT_TRUE(r.renderScene(layout, Pose{}, depth.view(), label.view()));
		pad = projectorPadding(K, p.baselineMm, 400);
		proj = DepthImageMm(K.width + pad, K.height);
		EXPECT_TRUE(r.renderScene(layout, SceneRenderer::projectorView(Pose{}, p.baselineMm),
					  proj.view(), {}, RenderWindow{-pad, 0}));
	}

	DepthImage16 sense(const KinectParams &p, uint64_t seed)
	{
		SensorScene s;
		s.depth = depth.view();
		s.label = label.view();
		s.projector = proj.view();
		s.projectorX0 = -pad;
		SynthRandom rng(seed);
		return simulateKinect(s, K, p, rng);
	}
};

TEST(KinectSensor, ProjectorShadowFallsLeftOfTheForeground)
{
	KinectParams p = quietParams();
	p.lateralPx = 0;
	p.lateralGrazing = 0;
	p.fatteningPx = 0;
	ShadowScene s(p);
	const DepthImage16 out = s.sense(p, 1);
	// Box front face at 700 mm (its top toward the camera), wall at 1000 mm.
	const int row = static_cast<int>(s.K.cy);
	int left = -1, right = -1;
	for (int x = 0; x < s.K.width; ++x) {
		if (s.label.at(x, row) == 1) {
			if (left < 0)
				left = x;
			right = x;
		}
	}
	ASSERT_GT(left, 0);
	// Expected width: fx b (1/700 - 1/1000) = 18.4 px.
	const double width = s.K.fx * p.baselineMm * (1.0 / 700 - 1.0 / 1000);
	int missingLeft = 0, missingRight = 0;
	for (int dx = 1; dx <= static_cast<int>(width) - 1; ++dx) {
		missingLeft += out.at(left - dx, row) == 0;
		missingRight += out.at(right + dx, row) == 0;
	}
	EXPECT_GE(missingLeft, static_cast<int>(width) - 2);
	EXPECT_EQ(missingRight, 0);
	// Beyond the shadow the wall is measured again.
	EXPECT_GT(out.at(left - static_cast<int>(width) - 3, row), 0);
	// The box itself has depth.
	EXPECT_GT(out.at((left + right) / 2, row), 0);
}

TEST(KinectSensor, FullModelStillShadowsLeftAndFattensEdges)
{
	const KinectParams p; // everything on
	ShadowScene s(p);
	const DepthImage16 out = s.sense(p, 9);
	int left = 0, right = 0;
	for (int y = 200; y < 280; ++y) {
		int l = -1, r = -1;
		for (int x = 0; x < s.K.width; ++x)
			if (s.label.at(x, y) == 1) {
				if (l < 0)
					l = x;
				r = x;
			}
		if (l < 0)
			continue;
		for (int dx = 3; dx <= 15; ++dx) {
			left += out.at(l - dx, y) == 0;
			right += out.at(r + dx, y) == 0;
		}
	}
	EXPECT_GT(left, 5 * std::max(right, 1));
}

TEST(KinectSensor, GrazingSurfacesLoseDepth)
{
	// A plane tilted 85 degrees away from the camera gets (almost) no depth.
	const KinectParams p = quietParams();
	const CameraIntrinsics K = kinectV1Intrinsics();
	const DepthImageMm plane = test::tiltedPlane(K, 85, 1000, 600, 3000);
	SensorScene scene;
	scene.depth = plane.view();
	SynthRandom rng(4);
	const test::Kept kept = test::keptOf(plane, simulateKinect(scene, K, p, rng), 20);
	ASSERT_GT(kept.rendered, 5000);
	EXPECT_LT(kept.valid, kept.rendered / 20);
}

TEST(KinectSensor, DeterministicForASeed)
{
	const KinectParams p;
	ShadowScene s(p);
	const DepthImage16 a = s.sense(p, 77), b = s.sense(p, 77), c = s.sense(p, 78);
	EXPECT_TRUE(std::equal(a.pixels().begin(), a.pixels().end(), b.pixels().begin()));
	EXPECT_FALSE(std::equal(a.pixels().begin(), a.pixels().end(), c.pixels().begin()));
}

} // namespace
} // namespace ihf
