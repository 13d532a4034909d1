// SPDX-License-Identifier: MIT
// Normalisation into the unit cube (Eq. 1-2) and back.

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/features/unit_cube_frame.h"

using namespace ihf;

namespace {

std::vector<CloudPoint> boxCloud()
{
	// Extents 100 x 40 x 20 mm around (10, 20, 800), lopsided along x.
	std::vector<CloudPoint> c;
	std::mt19937 rng(1);
	std::uniform_real_distribution<float> ux(0, 1);
	for (int i = 0; i < 500; ++i) {
		CloudPoint p;
		const float t = ux(rng);
		p.p = {-40.0f + 100.0f * t * t, 0.0f + 40.0f * ux(rng), 790.0f + 20.0f * ux(rng)};
		c.push_back(p);
	}
	c[0].p = {-40, 0, 790};
	c[1].p = {60, 40, 810};
	return c;
}

} // namespace

TEST(UnitCubeFrame, BoxCentreKeepsTheCloudInside)
{
	const auto cloud = boxCloud();
	auto frame = makeUnitCubeFrame(cloud);
	ASSERT_TRUE(frame.ok());
	EXPECT_FLOAT_EQ(frame->alpha, 100.0f);
	EXPECT_TRUE(frame->centre.isApprox(Eigen::Vector3f(10, 20, 800)));

	std::vector<Eigen::Vector3f> unit(cloud.size());
	toUnitCube(cloud, *frame, unit);
	for (const auto &u : unit)
		EXPECT_TRUE((u.array() >= -1e-6f).all() && (u.array() <= 1.0f + 1e-6f).all());
	EXPECT_NEAR(unit[0].x(), 0.0f, 1e-6f);
	EXPECT_NEAR(unit[1].x(), 1.0f, 1e-6f);
	EXPECT_NEAR(depthExtent(unit), 0.2f, 1e-5f); // h = 20 / 100

	for (size_t i = 0; i < cloud.size(); ++i)
		EXPECT_TRUE(frame->toCamera(unit[i]).isApprox(cloud[i].p, 1e-6f));
}

TEST(UnitCubeFrame, MeanCentreAndScaleSpace)
{
	const auto cloud = boxCloud();
	auto mean = makeUnitCubeFrame(cloud, 1.0f, CubeCentre::kMean);
	ASSERT_TRUE(mean.ok());
	Eigen::Vector3d sum = Eigen::Vector3d::Zero();
	for (const auto &c : cloud)
		sum += c.p.cast<double>();
	EXPECT_TRUE(mean->centre.isApprox((sum / cloud.size()).cast<float>(), 1e-6f));
	std::vector<Eigen::Vector3f> unit(cloud.size());
	toUnitCube(cloud, *mean, unit);
	Eigen::Vector3d m = Eigen::Vector3d::Zero();
	for (const auto &u : unit)
		m += u.cast<double>();
	EXPECT_TRUE((m / unit.size()).isApprox(Eigen::Vector3d::Constant(0.5), 1e-5));

	// s = 2 halves the object in the unit cube: h halves, the frame maps back.
	auto s2 = makeUnitCubeFrame(cloud, 2.0f);
	ASSERT_TRUE(s2.ok());
	toUnitCube(cloud, *s2, unit);
	EXPECT_NEAR(depthExtent(unit), 0.1f, 1e-5f);
	EXPECT_NEAR(unit[0].x(), 0.25f, 1e-6f);
	EXPECT_NEAR(unit[1].x(), 0.75f, 1e-6f);
	EXPECT_TRUE(s2->toCamera(unit[5]).isApprox(cloud[5].p, 1e-6f));
	EXPECT_FLOAT_EQ(s2->mmPerUnit(), 200.0f);
}

TEST(UnitCubeFrame, RejectsDegenerateInput)
{
	EXPECT_FALSE(makeUnitCubeFrame({}).ok());
	std::vector<CloudPoint> one(3);
	EXPECT_EQ(makeUnitCubeFrame(one).error().code, Errc::kInvalidArgument);
	EXPECT_FALSE(makeUnitCubeFrame(boxCloud(), 0.0f).ok());
}
