// SPDX-License-Identifier: MIT
// Training-set occlusion augmentation: deterministic, and it changes the
// descriptors of the views it cuts while their votes still point at the
// object's origin.
#include <gtest/gtest.h>

#include "core/geometry/mesh.h"
#include "core/geometry/ply_loader.h"
#include "core/training/training_set.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

const CameraIntrinsics kKinect{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};

class TrainingSetTest : public ::testing::Test
{
protected:
	void SetUp() override
	{
		auto mesh = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
		ASSERT_TRUE(mesh.ok());
		mesh_ = mesh.value();
		params_.objId = 1;
		params_.diameter = meshDiameter(mesh_);
		cfg_.views.viewpoints = 8;
		cfg_.views.inplaneSteps = 1;
		cfg_.views.minDistance = cfg_.views.maxDistance = 800;
		cfg_.scales = {1.0f};
		cfg_.partsPerImage = 6;
	}

	TrainingSet build(float occluded)
	{
		TrainingSetConfig c = cfg_;
		c.occludedViews = occluded;
		auto s = buildTrainingSet(mesh_, kKinect, params_, c);
		EXPECT_TRUE(s.ok());
		return s.ok() ? std::move(s.value()) : TrainingSet{};
	}

	Mesh mesh_;
	ModelParams params_;
	TrainingSetConfig cfg_;
};

TEST_F(TrainingSetTest, OcclusionAugmentationIsDeterministicAndChangesDescriptors)
{
	TrainingSet clean = build(0.0f);
	TrainingSet a = build(1.0f), b = build(1.0f);
	ASSERT_GT(clean.samples.size(), 0u);
	ASSERT_GT(a.samples.size(), 0u);
	EXPECT_EQ(a.histograms, b.histograms);
	ASSERT_EQ(a.labels.size(), b.labels.size());
	for (size_t i = 0; i < a.labels.size(); ++i)
		EXPECT_EQ(a.labels[i].offset, b.labels[i].offset);
	EXPECT_NE(a.histograms, clean.histograms);
	// A cut view still votes for the object: offsets stay within the
	// object's diameter of its origin.
	for (const Vote &v : a.labels)
		EXPECT_LT(v.offset.norm(), params_.diameter);
}

} // namespace
} // namespace ihf
