// SPDX-License-Identifier: MIT
// Back-projection and normals against analytic planes and spheres.

#include <vector>

#include <gtest/gtest.h>

#include "core/features/depth_cloud.h"
#include "tests/features/synthetic_depth.h"
#include "tests/ibs/alloc_counter.h"

using namespace ihf;
using test::lmoIntrinsics;

TEST(DepthCloud, PlanePointsAndNormals)
{
	const CameraIntrinsics k = lmoIntrinsics();
	DepthImageMm depth(k.width, k.height, 0.0f);
	const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.3, -1.0).normalized(); // faces the camera
	test::drawPlane(depth.view(), k, n, n.dot(Eigen::Vector3d(0, 0, 800)));
	depth.at(310, 250) = 0.0f; // a hole

	const PixelBox box{300, 240, 30, 20};
	std::vector<CloudPoint> cloud(box.w * box.h);
	auto count = cloudFromDepth(depth.view(), k, box, DepthCloudConfig{}, cloud);
	ASSERT_TRUE(count.ok());
	ASSERT_EQ(*count, box.w * box.h - 1);
	for (int i = 0; i < *count; ++i) {
		const CloudPoint &c = cloud[i];
		EXPECT_TRUE(box.contains(c.u, c.v));
		EXPECT_FALSE(c.u == 310 && c.v == 250);
		const float z = depth.at(c.u, c.v);
		EXPECT_FLOAT_EQ(c.p.z(), z);
		EXPECT_NEAR(c.p.x(), (c.u - k.cx) * z / k.fx, 1e-3);
		EXPECT_NEAR(c.p.y(), (c.v - k.cy) * z / k.fy, 1e-3);
		ASSERT_TRUE(c.hasNormal());
		EXPECT_GT(c.n.cast<double>().dot(n), 0.9999) << c.u << "," << c.v;
		EXPECT_LT(c.n.dot(c.p), 0.0f); // towards the camera
	}
}

// At a depth step the normals on both sides come from their own surface
// (one-sided differences), not from a mix across the edge.
TEST(DepthCloud, DiscontinuitiesAreNotDifferenced)
{
	const CameraIntrinsics k = lmoIntrinsics();
	DepthImageMm near(k.width, k.height, 0.0f), far(k.width, k.height, 0.0f);
	const Eigen::Vector3d nNear = Eigen::Vector3d(0.3, 0.0, -1.0).normalized();
	const Eigen::Vector3d nFar = Eigen::Vector3d(-0.2, 0.1, -1.0).normalized();
	test::drawPlane(near.view(), k, nNear, nNear.dot(Eigen::Vector3d(0, 0, 700)));
	test::drawPlane(far.view(), k, nFar, nFar.dot(Eigen::Vector3d(0, 0, 900)));
	DepthImageMm depth(k.width, k.height, 0.0f);
	for (int v = 0; v < k.height; ++v)
		for (int u = 0; u < k.width; ++u)
			depth.at(u, v) = u < 320 ? near.at(u, v) : far.at(u, v);

	const PixelBox box{310, 230, 20, 20};
	std::vector<CloudPoint> cloud(box.w * box.h);
	auto count = cloudFromDepth(depth.view(), k, box, DepthCloudConfig{}, cloud);
	ASSERT_TRUE(count.ok());
	ASSERT_EQ(*count, box.w * box.h);
	for (int i = 0; i < *count; ++i) {
		const CloudPoint &c = cloud[i];
		ASSERT_TRUE(c.hasNormal());
		const Eigen::Vector3d want = c.u < 320 ? nNear : nFar;
		EXPECT_GT(c.n.cast<double>().dot(want), 0.9999) << c.u << "," << c.v;
	}
}

TEST(DepthCloud, SphereNormalsAreRadial)
{
	const CameraIntrinsics k = lmoIntrinsics();
	DepthImageMm depth(k.width, k.height, 0.0f);
	const Eigen::Vector3d centre(20, -10, 750);
	test::drawSphere(depth.view(), k, centre, 60.0);
	const PixelBox box{250, 150, 160, 170};
	std::vector<CloudPoint> cloud(box.w * box.h);
	auto count = cloudFromDepth(depth.view(), k, box, DepthCloudConfig{}, cloud);
	ASSERT_TRUE(count.ok());
	ASSERT_GT(*count, 1000);
	int checked = 0;
	for (int i = 0; i < *count; ++i) {
		const CloudPoint &c = cloud[i];
		const Eigen::Vector3d radial = (c.p.cast<double>() - centre).normalized();
		// Away from the silhouette, where the surface is not grazing.
		if (radial.z() > -0.5)
			continue;
		ASSERT_TRUE(c.hasNormal());
		EXPECT_GT(c.n.cast<double>().dot(radial), 0.995);
		++checked;
	}
	EXPECT_GT(checked, 500);
}

TEST(DepthCloud, ClipsToImageAndReportsCapacity)
{
	const CameraIntrinsics k = lmoIntrinsics();
	DepthImageMm depth(k.width, k.height, 500.0f);
	std::vector<CloudPoint> cloud(100);
	auto count = cloudFromDepth(depth.view(), k, PixelBox{-5, -5, 10, 10}, DepthCloudConfig{}, cloud);
	ASSERT_TRUE(count.ok());
	EXPECT_EQ(*count, 25);
	EXPECT_EQ(cloudPixelBox(std::span<const CloudPoint>(cloud.data(), 25)).w, 5);

	auto full = cloudFromDepth(depth.view(), k, PixelBox{0, 0, 20, 20}, DepthCloudConfig{}, cloud);
	ASSERT_FALSE(full.ok());
	EXPECT_EQ(full.error().code, Errc::kCapacity);

	DepthCloudConfig strided;
	strided.pixelStride = 2;
	auto half = cloudFromDepth(depth.view(), k, PixelBox{0, 0, 20, 10}, strided, cloud);
	ASSERT_TRUE(half.ok());
	EXPECT_EQ(*half, 50);

	const size_t before = test::allocationCount();
	auto again = cloudFromDepth(depth.view(), k, PixelBox{100, 100, 10, 10}, DepthCloudConfig{}, cloud);
	EXPECT_EQ(test::allocationCount(), before);
	EXPECT_TRUE(again.ok());
}
