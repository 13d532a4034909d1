// SPDX-License-Identifier: MIT
// The window a box's poses are compared on pixel by pixel: a box whose
// window is downsampled is cropped again from the frame, as finely as the
// limit allows, in the same virtual camera; a box already at full
// resolution, or one the limit cannot crop finer, keeps its own window.

#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/estimator_workspace.h"
#include "core/estimation/part_window.h"
#include "core/estimation/virtual_crop.h"
#include "core/model/object_model.h"

namespace ihf {
namespace {

const CameraIntrinsics kFrameK{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};

// A frame of depth that varies from pixel to pixel (a tilted, rippled
// surface), so that crops at different resolutions differ.
std::vector<float> frameDepth()
{
	std::vector<float> d(static_cast<size_t>(kFrameK.width) * kFrameK.height);
	for (int y = 0; y < kFrameK.height; ++y)
		for (int x = 0; x < kFrameK.width; ++x)
			d[static_cast<size_t>(y * kFrameK.width + x)] =
				static_cast<float>(800.0 + 0.3 * x + 20.0 * std::sin(0.7 * x) * std::cos(0.5 * y));
	return d;
}

class PartWindowTest : public ::testing::Test
{
protected:
	PartWindowTest() : workspace_(EstimatorLimits{}), frame_(frameDepth()) {}

	ImageView<const float> frame() const
	{
		return ImageView<const float>(frame_.data(), kFrameK.width, kFrameK.height, kFrameK.width);
	}

	// kBox cropped into the workspace's window at up to `boxPixels`, as the
	// estimator crops it (crop_), and its part window at up to `limit`.
	PartWindow &partsOf(size_t boxPixels, int limit)
	{
		EXPECT_EQ(makeVirtualCrop(frame(), kFrameK, kBox, workspace_.cropBuffer().first(boxPixels), crop_),
			  CropStatus::kOk);
		EXPECT_TRUE(workspace_.beginBox(crop_.intrinsics.width, crop_.intrinsics.height));
		parts_.emplace(workspace_, model_, ScoreWindow{workspace_.observed(), crop_.intrinsics, OpenSides{}, nullptr},
			       crop_.validPixels);
		parts_->cropFiner(frame(), kFrameK, kBox, crop_.downsample, limit);
		return *parts_;
	}
	int limit() const { return workspace_.limits().maxWindowPixels; }

	static constexpr PixelBox kBox{300, 200, 100, 90};
	EstimatorWorkspace workspace_;
	std::vector<float> frame_;
	// The window only renders with its model; these tests render nothing.
	const OwnedObjectModel model_{ModelParams{}, Mesh{}, ForestStorage{}};
	VirtualCrop crop_;
	std::optional<PartWindow> parts_;
};

TEST_F(PartWindowTest, ADownsampledBoxIsCroppedAgainAtTheLimit)
{
	PartWindow &parts = partsOf(1000, limit());
	ASSERT_GT(crop_.downsample, 1);

	// The crop the estimator would make of the box at the limit, made here
	// apart.
	std::vector<float> buffer(static_cast<size_t>(limit()));
	VirtualCrop full;
	ASSERT_EQ(makeVirtualCrop(frame(), kFrameK, kBox, buffer, full), CropStatus::kOk);
	ASSERT_EQ(full.downsample, 1);

	const ImageView<const float> observed = parts.observed();
	EXPECT_TRUE(parts.finer());
	const CameraIntrinsics &K = parts.intrinsics();
	EXPECT_EQ(K.fx, full.intrinsics.fx);
	EXPECT_EQ(K.cx, full.intrinsics.cx);
	EXPECT_EQ(K.cy, full.intrinsics.cy);
	ASSERT_EQ(observed.width, full.intrinsics.width);
	ASSERT_EQ(observed.height, full.intrinsics.height);
	int differing = 0;
	for (int y = 0; y < observed.height; ++y)
		for (int x = 0; x < observed.width; ++x)
			differing += observed.at(x, y) != full.depth.at(x, y);
	EXPECT_EQ(differing, 0);
	EXPECT_EQ(parts.validPixels(), full.validPixels);
	EXPECT_DOUBLE_EQ(parts.fineness(), static_cast<double>(observed.width) * observed.height /
						  (crop_.intrinsics.width * crop_.intrinsics.height));
	EXPECT_GT(parts.fineness(), 4.0);
	// The box's own window is left as it was: the rest of the box is
	// scored there.
	EXPECT_NE(observed.data, workspace_.observed().data);

	// Its renders are of its size, each slot's apart from the box's.
	EXPECT_EQ(parts.reference().width, observed.width);
	EXPECT_EQ(parts.rendered(0).height, observed.height);
	EXPECT_NE(parts.rendered(0).data, workspace_.slot(0).render.data);
	EXPECT_NE(parts.rendered(0).data, parts.reference().data);
}

TEST_F(PartWindowTest, ABoxAtFullResolutionKeepsItsWindow)
{
	PartWindow &parts = partsOf(static_cast<size_t>(limit()), limit());
	ASSERT_EQ(crop_.downsample, 1);
	EXPECT_EQ(parts.observed().data, workspace_.observed().data);
	EXPECT_FALSE(parts.finer());
	EXPECT_EQ(parts.intrinsics().fx, crop_.intrinsics.fx);
	EXPECT_EQ(parts.validPixels(), crop_.validPixels);
	EXPECT_EQ(parts.fineness(), 1.0);
	EXPECT_EQ(parts.reference().data, workspace_.reference().data);
	EXPECT_EQ(parts.rendered(0).data, workspace_.slot(0).render.data);
}

TEST_F(PartWindowTest, ALimitNoFinerThanTheBoxKeepsItsWindow)
{
	// Downsampled by 2 into 3,000 pixels; a limit of 3,000 crops no finer.
	PartWindow &parts = partsOf(3000, 3000);
	ASSERT_EQ(crop_.downsample, 2);
	EXPECT_EQ(parts.observed().data, workspace_.observed().data);
	EXPECT_FALSE(parts.finer());
}

} // namespace
} // namespace ihf
