// SPDX-License-Identifier: MIT
// An object compared with itself turned, view by view: no turn changes
// nothing, a true symmetry changes (almost) nothing, a turn that swaps a
// box's long and short sides changes much of every view, and a turn that
// only the views' depth can tell (beyond the tolerance) is counted; a
// comparison sure to pass its limit stops early.

#include <gtest/gtest.h>

#include "core/synth/primitive_mesh.h"
#include "core/training/turn_views.h"

namespace ihf {
namespace {

const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

// A 100 x 60 x 40 mm box standing on z = 0 (its centre at z = 20), and its
// views.
class TurnViewsTest : public ::testing::Test
{
protected:
	const Mesh box_ = makeBox(100, 60, 40);
	TurnViews views_{box_};
};

TEST_F(TurnViewsTest, NoTurnChangesNothing)
{
	const TurnLook look = views_.compare(kZ, {0, 0, 20}, 0.0);
	EXPECT_EQ(look.meanShare, 0.0);
	EXPECT_EQ(look.alikeViews, 1.0);
}

TEST_F(TurnViewsTest, ABoxTurnedHalfRoundAboutItsCentreLooksTheSame)
{
	const TurnLook look = views_.compare(kZ, {0, 0, 20}, 180.0);
	EXPECT_LT(look.meanShare, 0.01);
	EXPECT_EQ(look.alikeViews, 1.0);
}

TEST_F(TurnViewsTest, ABoxTurnedAQuarterShowsItsOtherSide)
{
	const TurnLook look = views_.compare(kZ, {0, 0, 20}, 90.0);
	EXPECT_GT(look.meanShare, 0.2);
	EXPECT_LT(look.alikeViews, 0.5);
}

TEST_F(TurnViewsTest, ATurnAboutAnAxisBesideTheCentreMovesTheBox)
{
	// Half round about an axis 30 mm off the centre: the box lands 60 mm
	// away, more than half of a 60 mm side.
	const TurnLook look = views_.compare(kZ, {0, 30, 20}, 180.0);
	EXPECT_GT(look.meanShare, 0.5);
	EXPECT_EQ(look.alikeViews, 0.0);
}

TEST_F(TurnViewsTest, DepthsWithinTheToleranceAgree)
{
	// Half round about x through a point 1 mm above the centre: the box
	// moves 2 mm up (a twentieth of its height). Within the default tolerance
	// (6 mm for this box) only the band of its outline differs; within
	// 0.6 mm the faces seen end on differ too.
	TurnViewsConfig tight;
	tight.toleranceShare = 0.005;
	TurnViews b(box_, tight);
	const TurnLook within = views_.compare(Eigen::Vector3d::UnitX(), {0, 0, 21}, 180.0);
	const TurnLook beyond = b.compare(Eigen::Vector3d::UnitX(), {0, 0, 21}, 180.0);
	EXPECT_LT(within.meanShare, 0.25);
	EXPECT_GT(beyond.meanShare, within.meanShare + 0.1);
}

TEST_F(TurnViewsTest, GivesUpOnceTheLimitIsSureToBePassed)
{
	const TurnLook full = views_.compare(kZ, {0, 0, 20}, 90.0);
	const TurnLook cut = views_.compare(kZ, {0, 0, 20}, 90.0, 0.1);
	EXPECT_GT(cut.meanShare, 0.1);
	EXPECT_LE(cut.meanShare, full.meanShare);
	// Under the limit nothing changes.
	const TurnLook symmetric = views_.compare(kZ, {0, 0, 20}, 180.0, 0.1);
	EXPECT_EQ(symmetric.meanShare, views_.compare(kZ, {0, 0, 20}, 180.0).meanShare);
	EXPECT_EQ(symmetric.alikeViews, 1.0);
}

} // namespace
} // namespace ihf
