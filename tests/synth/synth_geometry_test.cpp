// SPDX-License-Identifier: MIT
// Random streams, primitives, resting poses, footprints and detection boxes.

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/geometry/ply_loader.h"
#include "core/synth/detection_box.h"
#include "core/synth/primitive_mesh.h"
#include "core/synth/resting_poses.h"
#include "core/synth/synth_random.h"
#include "core/synth/table_footprint.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

TEST(SynthRandom, SameSeedSameStreamDifferentSeedDifferent)
{
	SynthRandom a(42), b(42), c(43);
	bool differs = false;
	for (int i = 0; i < 1000; ++i) {
		const double x = a.normal(), y = b.normal(), z = c.normal();
		EXPECT_EQ(x, y);
		differs |= x != z;
	}
	EXPECT_TRUE(differs);
	// mt19937_64's 10000th output is fixed by the C++ standard.
	SynthRandom d(5489u);
	for (int i = 0; i < 9999; ++i)
		d.next();
	EXPECT_EQ(d.next(), 9981545732273789042ull);
	EXPECT_NE(mixSeed(1, 2), mixSeed(2, 1));
}

TEST(SynthRandom, DistributionsHaveTheirMoments)
{
	SynthRandom r(7);
	const int n = 200000;
	double s = 0, s2 = 0, u = 0;
	int counts[5] = {};
	for (int i = 0; i < n; ++i) {
		const double x = r.normal();
		s += x;
		s2 += x * x;
		u += r.uniform01();
		++counts[r.below(5)];
	}
	EXPECT_NEAR(s / n, 0.0, 0.01);
	EXPECT_NEAR(std::sqrt(s2 / n), 1.0, 0.01);
	EXPECT_NEAR(u / n, 0.5, 0.005);
	for (int c : counts)
		EXPECT_NEAR(c, n / 5, n / 100);
	for (int i = 0; i < 1000; ++i) {
		const int v = r.uniformInt(-3, 3);
		EXPECT_GE(v, -3);
		EXPECT_LE(v, 3);
	}
}

void expectOutwardNormals(const Mesh &m, const Eigen::Vector3f &inside)
{
	ASSERT_TRUE(m.hasNormals());
	for (const auto &f : m.faces) {
		const Eigen::Vector3f a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
		const Eigen::Vector3f n = (b - a).cross(c - a);
		if (n.norm() < 1e-6f)
			continue;
		EXPECT_GT(n.dot((a + b + c) / 3 - inside), 0.0f);
	}
}

TEST(PrimitiveMesh, SizesStandOnTheTableAndFaceOutwards)
{
	const Mesh box = makeBox(40, 60, 80);
	Aabb bb = boundingBox(box);
	EXPECT_FLOAT_EQ(bb.min.z(), 0.0f);
	EXPECT_FLOAT_EQ(bb.max.z(), 80.0f);
	EXPECT_FLOAT_EQ(bb.size().x(), 40.0f);
	EXPECT_FLOAT_EQ(bb.size().y(), 60.0f);
	expectOutwardNormals(box, {0, 0, 40});

	const Mesh cyl = makeCylinder(25, 100);
	bb = boundingBox(cyl);
	EXPECT_NEAR(bb.size().x(), 50.0f, 1e-3f);
	EXPECT_FLOAT_EQ(bb.max.z(), 100.0f);
	expectOutwardNormals(cyl, {0, 0, 50});

	const Mesh lying = makeLyingCylinder(20, 120);
	bb = boundingBox(lying);
	EXPECT_NEAR(bb.min.z(), 0.0f, 1e-4f);
	EXPECT_NEAR(bb.max.z(), 40.0f, 1e-3f);
	EXPECT_NEAR(bb.size().x(), 120.0f, 1e-3f);
	expectOutwardNormals(lying, {0, 0, 20});

	const Mesh sphere = makeSphere(30);
	bb = boundingBox(sphere);
	EXPECT_NEAR(bb.min.z(), 0.0f, 1e-4f);
	EXPECT_NEAR(bb.max.z(), 60.0f, 1e-4f);
	expectOutwardNormals(sphere, {0, 0, 30});
}

TEST(RestingPoses, BoxRestsOnItsFacesLargestFacesMostOften)
{
	// A 20 x 40 x 100 brick: six faces, the two 40 x 100 faces catch the
	// most drops, the 20 x 40 ends the fewest.
	const Mesh brick = makeBox(20, 40, 100);
	const auto result = computeRestingPoses(brick);
	ASSERT_TRUE(result) << result.error().message;
	const auto &poses = *result;
	ASSERT_EQ(poses.size(), 6u);
	double total = 0;
	for (const auto &p : poses) {
		total += p.probability;
		// Every pose is flat: one of the box's dimensions is the height.
		const double h = p.max.z() - p.min.z();
		EXPECT_TRUE(std::abs(h - 20) < 0.1 || std::abs(h - 40) < 0.1 || std::abs(h - 100) < 0.1) << h;
	}
	EXPECT_NEAR(total, 1.0, 1e-9);
	EXPECT_NEAR(poses[0].max.z() - poses[0].min.z(), 20.0, 0.1);
	EXPECT_NEAR(poses[5].max.z() - poses[5].min.z(), 100.0, 0.1);
	EXPECT_GT(poses[0].probability, 2 * poses[5].probability);
}

TEST(RestingPoses, ModelPosesAreLocalMinimaOfTheCentreOfMassHeight)
{
	for (const char *name : {"obj_000001.ply", "obj_000005.ply", "obj_000008.ply", "obj_000011.ply"}) {
	SCOPED_TRACE(name);
	auto mesh = loadPly(test::lmoDir() / "models" / name);
	ASSERT_TRUE(mesh) << mesh.error().message;
	const auto result = computeRestingPoses(*mesh);
	ASSERT_TRUE(result) << result.error().message;
	const auto &poses = *result;
	ASSERT_FALSE(poses.empty());
	const Eigen::Vector3d com = centreOfMass(*mesh);
	auto comHeight = [&](const Eigen::Matrix3d &R) {
		Eigen::Vector3d lo, hi;
		rotatedBounds(*mesh, R, lo, hi);
		return (R * com).z() - lo.z();
	};
	for (const auto &p : poses) {
		const double h0 = comHeight(p.R);
		// Tipping the object by 3 degrees about any horizontal axis does
		// not lower its centre of mass: the pose is stable.
		for (int k = 0; k < 8; ++k) {
			const double a = k * std::numbers::pi / 4;
			const Eigen::Vector3d axis(std::cos(a), std::sin(a), 0);
			const Eigen::Matrix3d tip =
				Eigen::AngleAxisd(3.0 * std::numbers::pi / 180, axis).toRotationMatrix();
			EXPECT_GT(comHeight(tip * p.R), h0 - 1e-6);
		}
	}
	}
}

TEST(Footprint, OverlapAndContainment)
{
	Footprint a{{0, 0}, {10, 10}, 0};
	Footprint b{{25, 0}, {10, 10}, 0};
	EXPECT_FALSE(footprintsOverlap(a, b));
	EXPECT_TRUE(footprintsOverlap(a, b, 6.0));
	// Rotated by 45 degrees, b's corner reaches 14.14 towards a.
	b.yaw = std::numbers::pi / 4;
	EXPECT_FALSE(footprintsOverlap(a, b));
	b.centre = {24, 0};
	EXPECT_TRUE(footprintsOverlap(a, b));
	Footprint table{{0, 0}, {100, 50}, 0};
	EXPECT_TRUE(footprintInside(a, table));
	a.centre = {95, 0};
	EXPECT_FALSE(footprintInside(a, table));
}

TEST(DetectionBox, EnlargedShiftedClippedAndCoveringTheObject)
{
	SynthRandom rng(3);
	double coveredSum = 0;
	int coveredCount = 0;
	for (int i = 0; i < 2000; ++i) {
		const std::array<int, 4> box{rng.uniformInt(-60, 600), rng.uniformInt(-60, 440),
					     rng.uniformInt(20, 200), rng.uniformInt(20, 200)};
		const Detection d = coarseDetection(box, 640, 480, 2, i, 5, rng);
		EXPECT_EQ(d.categoryId, 5);
		EXPECT_EQ(d.imageId, i);
		EXPECT_GE(d.bbox[0], 0.0);
		EXPECT_GE(d.bbox[1], 0.0);
		EXPECT_LE(d.bbox[0] + d.bbox[2], 640.0 + 1e-9);
		EXPECT_LE(d.bbox[1] + d.bbox[3], 480.0 + 1e-9);
		// Area of the object's in-image box the detection covers.
		const double ox0 = std::max(box[0], 0), oy0 = std::max(box[1], 0);
		const double ox1 = std::min(box[0] + box[2], 640), oy1 = std::min(box[1] + box[3], 480);
		if (ox1 - ox0 < 1 || oy1 - oy0 < 1)
			continue;
		const double ix = std::max(0.0, std::min(ox1, d.bbox[0] + d.bbox[2]) - std::max(ox0, d.bbox[0]));
		const double iy = std::max(0.0, std::min(oy1, d.bbox[1] + d.bbox[3]) - std::max(oy0, d.bbox[1]));
		const double covered = ix * iy / ((ox1 - ox0) * (oy1 - oy0));
		EXPECT_GE(covered, 0.7);
		coveredSum += covered;
		++coveredCount;
		// Unclipped, the box is 5-25 % larger than the object's.
		if (box[0] > 40 && box[1] > 40 && box[0] + box[2] < 600 && box[1] + box[3] < 440) {
			EXPECT_GE(d.bbox[2], 1.05 * box[2] - 0.1);
			EXPECT_LE(d.bbox[2], 1.25 * box[2] + 0.1);
		}
	}
	// On average the box holds almost all of the object.
	EXPECT_GE(coveredSum / coveredCount, 0.9);
}

} // namespace
} // namespace ihf
