// SPDX-License-Identifier: MIT
// The rotation bank: proper rotations, off at zero size, and it covers
// SO(3): every random rotation has a bank entry within the bound below.

#include <random>

#include <gtest/gtest.h>

#include "core/geometry/pose.h"
#include "core/pose/rotation_bank.h"

namespace ihf {
namespace {

TEST(RotationBank, EntriesAreRotationsAndTheBankCoversSO3)
{
	RotationBankConfig c;
	c.viewpoints = 40;
	c.inplane = 8;
	ASSERT_EQ(rotationBankSize(c), 320);
	std::vector<Eigen::Matrix3d> bank;
	for (int i = 0; i < rotationBankSize(c); ++i) {
		bank.push_back(rotationBankEntry(c, i));
		EXPECT_NEAR(bank.back().determinant(), 1.0, 1e-9);
		EXPECT_TRUE((bank.back() * bank.back().transpose()).isIdentity(1e-9));
	}
	std::mt19937_64 rng(4);
	std::normal_distribution<double> n(0, 1);
	double worst = 0;
	for (int k = 0; k < 2000; ++k) {
		const Eigen::Matrix3d R =
			Eigen::Quaterniond(Eigen::Vector4d(n(rng), n(rng), n(rng), n(rng)).normalized()).toRotationMatrix();
		double nearest = M_PI;
		for (const auto &B : bank)
			nearest = std::min(nearest, rotationAngle(R, B));
		worst = std::max(worst, nearest);
	}
	// 320 entries: a view direction within ~20 deg and a turn within 22.5.
	EXPECT_LT(worst * 180.0 / M_PI, 36.0);
	RecordProperty("worst_deg", std::to_string(worst * 180.0 / M_PI));
}

TEST(RotationBank, OffWithoutViewpointsOrTurns)
{
	RotationBankConfig c;
	EXPECT_EQ(rotationBankSize(c), 0); // off by default
	c.viewpoints = 10;
	c.inplane = 0;
	EXPECT_EQ(rotationBankSize(c), 0);
}

} // namespace
} // namespace ihf
