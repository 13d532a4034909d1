// SPDX-License-Identifier: MIT
// Two poses compared where their renders differ: a part only one draws is
// evidence for it where the depth shows the part, and against it where the
// depth lies behind; an occluder in front of both, or no depth, is none.

#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/part_evidence.h"

namespace ihf {
namespace {

constexpr int kW = 20, kH = 10;

struct Images {
	std::vector<float> observed = std::vector<float>(kW * kH, 900.0f); // the wall behind
	std::vector<float> a = std::vector<float>(kW * kH, 0.0f);
	std::vector<float> b = std::vector<float>(kW * kH, 0.0f);

	static void fill(std::vector<float> &img, int x0, int x1, float depth)
	{
		for (int y = 0; y < kH; ++y)
			for (int x = x0; x < x1; ++x)
				img[static_cast<size_t>(y * kW + x)] = depth;
	}
	PartEvidence compare() const
	{
		return comparePoseRenders(ImageView<const float>(observed.data(), kW, kH),
					  ImageView<const float>(a.data(), kW, kH),
					  ImageView<const float>(b.data(), kW, kH), 10.0f);
	}
};

// A body both draw (columns 5-14), A's handle on the left (2-4), B's on the
// right (15-17); the sensor sees A's.
Images cupScene()
{
	Images s;
	Images::fill(s.a, 5, 15, 600.0f);
	Images::fill(s.b, 5, 15, 603.0f); // within the tolerance: no difference
	Images::fill(s.a, 2, 5, 590.0f);
	Images::fill(s.b, 15, 18, 590.0f);
	Images::fill(s.observed, 5, 15, 601.0f);
	Images::fill(s.observed, 2, 5, 592.0f);
	return s;
}

TEST(PartEvidence, ThePartSeenAndThePartSeenThroughBothFavourTheRightPose)
{
	const PartEvidence e = cupScene().compare();
	EXPECT_EQ(e.differing, 2 * 3 * kH);   // both handles' columns, nothing of the body
	EXPECT_EQ(e.forA, 2 * 3 * kH);        // A's handle explained, B's seen through
	EXPECT_EQ(e.forB, 0);
	EXPECT_EQ(e.informative, e.forA);
	// Swapped, the evidence swaps.
	Images s = cupScene();
	std::swap(s.a, s.b);
	const PartEvidence swapped = s.compare();
	EXPECT_EQ(swapped.forB, e.forA);
	EXPECT_EQ(swapped.forA, 0);
}

TEST(PartEvidence, AnOccluderOrMissingDepthIsNoEvidence)
{
	Images s = cupScene();
	Images::fill(s.observed, 0, 5, 300.0f);   // something in front of A's handle
	Images::fill(s.observed, 15, 20, 0.0f);   // no depth where B's handle would be
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.differing, 2 * 3 * kH);
	EXPECT_EQ(e.informative, 0);
	EXPECT_EQ(e.forA, 0);
	EXPECT_EQ(e.forB, 0);
}

TEST(PartEvidence, AHiddenPartLeavesNothingToCompare)
{
	// Neither pose draws a part in view: the renders agree everywhere.
	Images s;
	Images::fill(s.a, 5, 15, 600.0f);
	Images::fill(s.b, 5, 15, 600.0f);
	Images::fill(s.observed, 5, 15, 600.0f);
	const PartEvidence e = s.compare();
	EXPECT_EQ(e.differing, 0);
	EXPECT_EQ(e.informative, 0);
}

} // namespace
} // namespace ihf
