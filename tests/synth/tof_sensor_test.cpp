// SPDX-License-Identifier: MIT
// The time-of-flight model: shot noise against its formula and white per
// pixel, mixed pixels between the two surfaces of an edge (and none away
// from edges), no projector shadow, the amplitude limit at grazing angles
// and far away, and determinism.

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/synth/primitive_mesh.h"
#include "core/synth/scene_render.h"
#include "core/synth/tof_sensor.h"
#include "tests/synth/tilted_plane.h"

namespace ihf {
namespace {

// Parameters with the random dropout and the wiggling off, to look at one effect.
TofParams quietParams()
{
	TofParams p;
	p.pixelDropout = 0;
	p.wiggleMm = 0;
	return p;
}

DepthImage16 sensePlane(double zMm, const TofParams &p, uint64_t seed)
{
	const CameraIntrinsics K = kinectV1Intrinsics();
	DepthImageMm plane(K.width, K.height, static_cast<float>(zMm));
	SensorScene scene;
	scene.depth = plane.view();
	SynthRandom rng(seed);
	return simulateTof(scene, K, p, rng);
}

TEST(TofSensor, NoiseFollowsTheShotNoiseFormula)
{
	const TofParams p = quietParams();
	EXPECT_NEAR(tofAxialSigmaMm(p, 1000, 0), 1.5, 1e-12);
	EXPECT_NEAR(tofAxialSigmaMm(p, 2000, 0), 3.0, 1e-12);
	EXPECT_NEAR(tofAxialSigmaMm(p, 1000, std::numbers::pi / 3), 1.5 * std::sqrt(2.0), 1e-12);
	for (double z : {800.0, 1500.0, 2500.0}) {
		const DepthImage16 out = sensePlane(z, p, 3);
		double sum = 0, sum2 = 0, lag = 0;
		int n = 0, pairs = 0;
		for (int y = 0; y < out.height(); ++y)
			for (int x = 0; x < out.width(); ++x) {
				const uint16_t v = out.at(x, y);
				if (!v)
					continue;
				sum += v;
				sum2 += static_cast<double>(v) * v;
				++n;
			}
		ASSERT_GT(n, out.width() * out.height() * 9 / 10) << z;
		const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
		// Millimetre rounding adds 1/12 mm^2 of variance.
		const double model = std::sqrt(std::pow(tofAxialSigmaMm(p, z, 0), 2) + 1.0 / 12);
		EXPECT_NEAR(mean, z, 0.1) << z;
		EXPECT_NEAR(sd, model, 0.05 * model) << z;
		// White: neighbours are uncorrelated (the Kinect's are not).
		for (int y = 0; y < out.height(); ++y)
			for (int x = 0; x + 1 < out.width(); ++x)
				if (out.at(x, y) && out.at(x + 1, y)) {
					lag += (out.at(x, y) - mean) * (out.at(x + 1, y) - mean);
					++pairs;
				}
		EXPECT_LT(std::abs(lag / pairs) / (sd * sd), 0.05) << z;
	}
}

TEST(TofSensor, WigglingIsPeriodicAndSmall)
{
	TofParams p = quietParams();
	p.sigmaRefMm = 0.01;
	p.wiggleMm = 2.0;
	double lo = 1e9, hi = -1e9;
	for (double z = 1000; z < 1000 + p.wigglePeriodMm; z += 50) {
		const DepthImage16 out = sensePlane(z, p, 11);
		const double bias = out.at(320, 240) - z;
		lo = std::min(lo, bias);
		hi = std::max(hi, bias);
	}
	// Over one period the bias sweeps its whole amplitude, no more.
	EXPECT_GE(hi, 1.4);
	EXPECT_LE(hi, 2.5);
	EXPECT_LE(lo, -1.4);
	EXPECT_GE(lo, -2.5);
}

TEST(TofSensor, MixedDepthIsWeightedByCoverageAndBrightness)
{
	EXPECT_DOUBLE_EQ(tofMixedDepth(700, 1000, 1.0), 700);
	EXPECT_DOUBLE_EQ(tofMixedDepth(700, 1000, 0.0), 1000);
	// Half and half: the nearer, brighter surface pulls harder.
	const double m = tofMixedDepth(700, 1000, 0.5);
	EXPECT_GT(m, 700);
	EXPECT_LT(m, 850);
	EXPECT_NEAR(tofMixedDepth(1000, 700, 0.5), m, 1e-9);
}

// A 100 mm box standing 300 mm in front of a wall at 1 m, both fronto-parallel.
struct EdgeScene {
	CameraIntrinsics K = kinectV1Intrinsics();
	DepthImageMm depth{K.width, K.height};
	Image<uint16_t> label{K.width, K.height};

	EdgeScene()
	{
		SceneLayout layout;
		SceneObject wall, box;
		wall.role = SceneRole::kRoom;
		wall.mesh = std::make_shared<const Mesh>(makeQuad(4000, 4000));
		wall.modelToWorld.R = Eigen::Vector3d(1, -1, -1).asDiagonal();
		wall.modelToWorld.t = {0, 0, 1000};
		box.role = SceneRole::kTarget;
		box.mesh = std::make_shared<const Mesh>(makeBox(100, 100, 100));
		box.modelToWorld.R = Eigen::Vector3d(1, -1, -1).asDiagonal();
		box.modelToWorld.t = {0, 0, 800}; // front face at 700 mm
		layout.objects = {box, wall};
		SceneRenderer r(K, 1000);
		EXPECT_TRUE(r.renderScene(layout, Pose{}, depth.view(), label.view()));
	}

	DepthImage16 sense(const TofParams &p, uint64_t seed) const
	{
		SensorScene s;
		s.depth = depth.view();
		s.label = label.view();
		SynthRandom rng(seed);
		return simulateTof(s, K, p, rng);
	}

	// Distance in pixels (Chebyshev) to the nearest pixel of the other surface.
	int edgeDistance(int x, int y) const
	{
		const bool box = label.at(x, y) == 1;
		for (int r = 1; r < 6; ++r)
			for (int dy = -r; dy <= r; ++dy)
				for (int dx = -r; dx <= r; ++dx) {
					const int nx = x + dx, ny = y + dy;
					if (nx >= 0 && ny >= 0 && nx < K.width && ny < K.height &&
					    (label.at(nx, ny) == 1) != box)
						return r;
				}
		return 99;
	}
};

TEST(TofSensor, MixedPixelsFloatBetweenTheSurfacesOfAnEdgeOnly)
{
	TofParams p = quietParams();
	p.flyingInvalid = 0; // keep them all
	const EdgeScene s;
	const DepthImage16 out = s.sense(p, 5);
	int floating = 0, edgePixels = 0, boxOrWall = 0;
	for (int y = 0; y < s.K.height; ++y)
		for (int x = 0; x < s.K.width; ++x) {
			const int v = out.at(x, y);
			const int d = s.edgeDistance(x, y);
			if (d == 1)
				++edgePixels;
			// Noise is ~1-2 mm here: 20 mm off both surfaces is floating.
			const bool between = v > 720 && v < 980;
			if (between) {
				++floating;
				EXPECT_EQ(d, 1) << x << "," << y << " " << v;
			} else if (v) {
				++boxOrWall;
			}
		}
	ASSERT_GT(edgePixels, 200);
	// The own coverage is at least half: most edge pixels float, a few sit
	// within 20 mm of their own surface.
	EXPECT_GT(floating, edgePixels / 2);
	EXPECT_GT(boxOrWall, s.K.width * s.K.height / 2);

	// The camera's filter removes them all at 1: nothing floats, the edge
	// pixels have no depth and the rest keep theirs.
	p.flyingInvalid = 1;
	const DepthImage16 filtered = s.sense(p, 5);
	int holes = 0;
	for (int y = 0; y < s.K.height; ++y)
		for (int x = 0; x < s.K.width; ++x) {
			const int v = filtered.at(x, y);
			EXPECT_FALSE(v > 720 && v < 980) << x << "," << y << " " << v;
			if (!v) {
				++holes;
				EXPECT_EQ(s.edgeDistance(x, y), 1) << x << "," << y;
			}
		}
	EXPECT_GT(holes, edgePixels / 2);
}

TEST(TofSensor, NoProjectorShadowBesideTheForeground)
{
	// The structured-light model loses an 18 px band of wall left of the
	// box (kinect_sensor_test); time of flight sees it.
	TofParams p = quietParams();
	p.flyingInvalid = 1;
	const EdgeScene s;
	const DepthImage16 out = s.sense(p, 7);
	const int row = static_cast<int>(s.K.cy);
	int left = -1;
	for (int x = 0; x < s.K.width; ++x)
		if (s.label.at(x, row) == 1) {
			left = x;
			break;
		}
	ASSERT_GT(left, 20);
	for (int dx = 2; dx <= 20; ++dx)
		EXPECT_NEAR(out.at(left - dx, row), 1000, 8) << dx;
}

TEST(TofSensor, TooLittleLightLeavesNoDepth)
{
	const TofParams p = quietParams();
	// Amplitude (1000 / z)^2: full at 2 m, none past 4.08 m (and the range
	// ends at 3.86 m), some dropout in the ramp above 0.06.
	auto validShare = [&](double z) {
		const DepthImage16 out = sensePlane(z, p, 13);
		int n = 0;
		for (uint16_t v : out.pixels())
			n += v > 0;
		return static_cast<double>(n) / (out.width() * out.height());
	};
	EXPECT_GT(validShare(2000), 0.99);
	EXPECT_LT(validShare(3600), 0.95);
	EXPECT_GT(validShare(3600), 0.05);
	EXPECT_EQ(validShare(3900), 0.0);

	// A plane at 2.5-3 m tilted 75 degrees away: cos(75) (1000 / z)^2 < 0.05,
	// though facing the camera at that distance it keeps its depth (0.13),
	// and its neighbours are far from an edge's jump (55 mm).
	EXPECT_GT(validShare(2750), 0.99);
	const CameraIntrinsics K = kinectV1Intrinsics();
	const DepthImageMm plane = test::tiltedPlane(K, 75, 2750, 2500, 3000);
	SensorScene scene;
	scene.depth = plane.view();
	SynthRandom rng(4);
	const test::Kept kept = test::keptOf(plane, simulateTof(scene, K, p, rng));
	ASSERT_GT(kept.rendered, 2000);
	EXPECT_LT(kept.valid, kept.rendered / 20);
}

TEST(TofSensor, DarkPatchesLoseDepthInBlobs)
{
	TofParams p = quietParams();
	const EdgeScene s;
	SensorScene scene;
	scene.depth = s.depth.view();
	scene.label = s.label.view();
	scene.labelDropout = {0.0f, 0.4f, 0.0f}; // the box is dark, the wall is not
	SynthRandom rng(17);
	const DepthImage16 out = simulateTof(scene, s.K, p, rng);
	int box = 0, boxLost = 0, wall = 0, wallLost = 0;
	for (int y = 0; y < s.K.height; ++y)
		for (int x = 0; x < s.K.width; ++x) {
			if (s.edgeDistance(x, y) <= 1)
				continue;
			const bool lost = out.at(x, y) == 0;
			if (s.label.at(x, y) == 1) {
				++box;
				boxLost += lost;
			} else if (s.label.at(x, y) == 2) {
				++wall;
				wallLost += lost;
			}
		}
	ASSERT_GT(box, 1000);
	EXPECT_NEAR(static_cast<double>(boxLost) / box, 0.4, 0.15);
	EXPECT_LT(static_cast<double>(wallLost) / wall, 0.01);
}

TEST(TofSensor, SameSeedSameImage)
{
	const TofParams p; // everything on
	const EdgeScene s;
	const DepthImage16 a = s.sense(p, 21), b = s.sense(p, 21), c = s.sense(p, 22);
	EXPECT_TRUE(std::equal(a.pixels().begin(), a.pixels().end(), b.pixels().begin()));
	EXPECT_FALSE(std::equal(a.pixels().begin(), a.pixels().end(), c.pixels().begin()));
}

} // namespace
} // namespace ihf
