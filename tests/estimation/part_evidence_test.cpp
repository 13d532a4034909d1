// SPDX-License-Identifier: MIT
// Two poses compared where their renders differ: a part only one draws is
// evidence for it where the depth shows the part, and against it where the
// depth lies behind; an occluder in front of both, or no depth, is none,
// and so is a surface that goes on beyond the part from its depth.

#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/part_evidence.h"

namespace ihf {
namespace {

constexpr int kW = 40, kH = 20;

struct Images {
	std::vector<float> observed = std::vector<float>(kW * kH, 900.0f); // the wall behind
	std::vector<float> a = std::vector<float>(kW * kH, 0.0f);
	std::vector<float> b = std::vector<float>(kW * kH, 0.0f);

	static void fill(std::vector<float> &img, int x0, int x1, float depth, int y0 = 0, int y1 = kH)
	{
		for (int y = y0; y < y1; ++y)
			for (int x = x0; x < x1; ++x)
				img[static_cast<size_t>(y * kW + x)] = depth;
	}
	PartEvidence compare(PoseDifference difference = PoseDifference::kPart) const
	{
		return comparePoseRenders(ImageView<const float>(observed.data(), kW, kH),
					  ImageView<const float>(a.data(), kW, kH),
					  ImageView<const float>(b.data(), kW, kH), 10.0f, difference);
	}
};

// A body both draw (columns 15-24), A's handle on the left (12-14), B's on
// the right (25-27), each over rows 5-14; the sensor sees A's.
constexpr int kHandleTop = 5, kHandleBottom = 15, kHandleRows = kHandleBottom - kHandleTop;

Images cupScene()
{
	Images s;
	Images::fill(s.a, 15, 25, 600.0f);
	Images::fill(s.b, 15, 25, 603.0f); // within the tolerance: no difference
	Images::fill(s.a, 12, 15, 590.0f, kHandleTop, kHandleBottom);
	Images::fill(s.b, 25, 28, 590.0f, kHandleTop, kHandleBottom);
	Images::fill(s.observed, 15, 25, 601.0f);
	Images::fill(s.observed, 12, 15, 592.0f, kHandleTop, kHandleBottom);
	return s;
}

TEST(PartEvidence, ThePartSeenAndThePartSeenThroughBothFavourTheRightPose)
{
	const PartEvidence e = cupScene().compare();
	EXPECT_EQ(e.differing, 2 * 3 * kHandleRows);   // both handles' columns, nothing of the body
	EXPECT_EQ(e.forA, 2 * 3 * kHandleRows);        // A's handle explained, B's seen through
	EXPECT_EQ(e.forB, 0);
	EXPECT_EQ(e.informative, e.forA);
	// Swapped, the evidence swaps.
	Images s = cupScene();
	std::swap(s.a, s.b);
	const PartEvidence swapped = s.compare();
	EXPECT_EQ(swapped.forB, e.forA);
	EXPECT_EQ(swapped.forA, 0);
}

TEST(PartEvidence, APartLyingOnASurfaceThatGoesOnIsNoEvidenceForIt)
{
	// A table at the depth of A's handle, going on to its left beyond
	// both outlines: A's handle explains depth that is there anyway. B's
	// handle, seen through, still counts against B.
	Images s = cupScene();
	Images::fill(s.observed, 0, 15, 592.0f, kHandleTop - 5, kHandleBottom + 5);
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.differing, 2 * 3 * kHandleRows);
	EXPECT_EQ(e.forA, 3 * kHandleRows);
	EXPECT_EQ(e.forB, 0);
	EXPECT_EQ(e.informative, 3 * kHandleRows);
	// Poses apart over their silhouettes are not checked for it.
	const PartEvidence whole = s.compare(PoseDifference::kSilhouette);
	EXPECT_EQ(whole.forA, 2 * 3 * kHandleRows);
	EXPECT_EQ(whole.forB, 0);
}

// The scene left of A's handle slants: at the handle's depth + offset
// beside it, 4 mm farther each pixel to the left.
void slantLeftOfHandle(Images &s, float offset)
{
	for (int y = kHandleTop - 5; y < kHandleBottom + 5; ++y)
		for (int x = 0; x < 12; ++x)
			s.observed[static_cast<size_t>(y * kW + x)] = 592.0f + offset + 4.0f * static_cast<float>(12 - x);
}

TEST(PartEvidence, APartLyingOnASlantedSurfaceIsNoEvidenceForIt)
{
	// A table seen at a slant, going on from under A's handle: 3 and 4
	// pixels past the outline it lies 16-24 mm from the handle's depth,
	// but it never steps on the way there.
	Images s = cupScene();
	slantLeftOfHandle(s, 0.0f);
	Images::fill(s.observed, 12, 15, 592.0f, kHandleTop - 5, kHandleTop);
	Images::fill(s.observed, 12, 15, 592.0f, kHandleBottom, kHandleBottom + 5);
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.forA, 3 * kHandleRows); // B's handle seen through, nothing for A's
	EXPECT_EQ(e.forB, 0);
	EXPECT_EQ(e.informative, 3 * kHandleRows);
}

TEST(PartEvidence, APartInFrontOfASlantedSurfaceStillCounts)
{
	// The same slant 30 mm behind the handle: the depth steps at its outline.
	Images s = cupScene();
	slantLeftOfHandle(s, 30.0f);
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.forA, 2 * 3 * kHandleRows);
	EXPECT_EQ(e.forB, 0);
}

TEST(PartEvidence, APartWhoseEdgeTheSensorBlursStillCounts)
{
	// The sensor bleeds the handle's depth two pixels past its outline;
	// beyond that lies the wall.
	Images s = cupScene();
	Images::fill(s.observed, 10, 12, 592.0f, kHandleTop - 2, kHandleBottom + 2);
	Images::fill(s.observed, 12, 15, 592.0f, kHandleTop - 2, kHandleTop);
	Images::fill(s.observed, 12, 15, 592.0f, kHandleBottom, kHandleBottom + 2);
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.forA, 2 * 3 * kHandleRows);
	EXPECT_EQ(e.forB, 0);
}

TEST(PartEvidence, AnOccluderOrMissingDepthIsNoEvidence)
{
	Images s = cupScene();
	Images::fill(s.observed, 10, 15, 300.0f); // something in front of A's handle
	Images::fill(s.observed, 25, 30, 0.0f);   // no depth where B's handle would be
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.differing, 2 * 3 * kHandleRows);
	EXPECT_EQ(e.informative, 0);
	EXPECT_EQ(e.forA, 0);
	EXPECT_EQ(e.forB, 0);
}

TEST(PartEvidence, AHiddenPartLeavesNothingToCompare)
{
	// Neither pose draws a part in view: the renders agree everywhere.
	Images s;
	Images::fill(s.a, 15, 25, 600.0f);
	Images::fill(s.b, 15, 25, 600.0f);
	Images::fill(s.observed, 15, 25, 600.0f);
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.differing, 0);
	EXPECT_EQ(e.informative, 0);
}

} // namespace
} // namespace ihf
