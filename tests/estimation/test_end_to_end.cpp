// SPDX-License-Identifier: MIT
// A small forest trained from a real mesh recovers a known pose on a clean
// render, end to end (training views -> parts -> forest -> file -> votes ->
// refinement); training is deterministic; bad boxes give "no pose".

#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "core/eval/pose_error.h"
#include "core/estimation/pose_estimator.h"
#include "core/forest/forest_trainer.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/rotation.h"
#include "core/model/forest_file.h"
#include "core/render/depth_renderer.h"
#include "core/training/hocp_split_metric.h"
#include "core/training/training_set.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

const CameraIntrinsics kKinect{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};

struct Trained {
	Mesh mesh;
	ModelParams params;
	HoughForest forest;
	TrainingSetConfig set;
};

Trained trainSmall(uint64_t seed)
{
	Trained t;
	auto mesh = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
	EXPECT_TRUE(mesh.ok());
	t.mesh = mesh.value();
	t.params.objId = 1;
	t.params.diameter = meshDiameter(t.mesh);
	t.set.views.viewpoints = 40;
	t.set.views.inplaneSteps = 4;
	t.set.views.minDistance = 750;
	t.set.views.maxDistance = 850;
	t.set.views.seed = seed;
	t.set.scales = {1.0f};
	t.set.partsPerImage = 20;
	t.set.seed = seed;
	auto set = buildTrainingSet(t.mesh, kKinect, t.params, t.set);
	EXPECT_TRUE(set.ok());
	HocpSplitMetric metric(*set, t.params.hocp, t.params.depthCheckMarginMm);
	ForestTrainerConfig fc;
	fc.seed = seed;
	t.forest = trainForest(fc, metric, set->labels);
	return t;
}

std::string readAll(const std::filesystem::path &p)
{
	std::ifstream f(p, std::ios::binary);
	return {std::istreambuf_iterator<char>(f), {}};
}

class EndToEnd : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		trained_ = new Trained(trainSmall(11));
		dir_ = new std::filesystem::path(test::freshTempDir("end_to_end"));
		ForestStorage storage(trained_->forest, TemplateEncoding::kUint8);
		ASSERT_TRUE(saveModelFile(*dir_ / "ape.ihf", trained_->params, trained_->mesh, storage.view()).ok());
		auto m = loadModelFile(*dir_ / "ape.ihf");
		ASSERT_TRUE(m.ok());
		model_ = m.value().release();
	}
	static void TearDownTestSuite()
	{
		delete model_;
		delete trained_;
		delete dir_;
	}

	static Trained *trained_;
	static ObjectModel *model_;
	static std::filesystem::path *dir_;
};

Trained *EndToEnd::trained_ = nullptr;
ObjectModel *EndToEnd::model_ = nullptr;
std::filesystem::path *EndToEnd::dir_ = nullptr;

TEST_F(EndToEnd, RecoversAKnownPoseOnACleanRender)
{
	// The appearance of a training view, placed off the optical axis: the
	// virtual crop must undo the off-axis rotation for the votes to fit.
	auto views = sampleTrainingViews(trained_->set.views);
	Pose gt;
	gt.t = Eigen::Vector3d(60, -40, 800);
	gt.R = rayAlignment(gt.t) * views[37].pose.R;

	DepthRenderer renderer(model_->mesh().vertices.size());
	DepthImageMm depth(640, 480, 0.0f);
	ASSERT_TRUE(renderer.render(model_->mesh(), gt, kKinect, depth.view()).ok());
	int x0 = 640, y0 = 480, x1 = 0, y1 = 0;
	for (int y = 0; y < 480; ++y)
		for (int x = 0; x < 640; ++x)
			if (depth.at(x, y) > 0) {
				x0 = std::min(x0, x);
				y0 = std::min(y0, y);
				x1 = std::max(x1, x);
				y1 = std::max(y1, y);
			}
	ASSERT_LT(x0, x1);
	const int mx = (x1 - x0) / 10 + 2, my = (y1 - y0) / 10 + 2;
	PixelBox box{x0 - mx, y0 - my, x1 - x0 + 1 + 2 * mx, y1 - y0 + 1 + 2 * my};

	PoseEstimator estimator;
	EstimatorConfig cfg;
	PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, cfg);
	ASSERT_TRUE(e.found) << e.reason;
	double add = addError(e.pose, gt, model_->mesh().vertices);
	EXPECT_LT(add, 0.1 * trained_->params.diameter)
		<< "rotation error " << rotationAngle(e.pose.R, gt.R) * 180 / M_PI << " deg, translation "
		<< (e.pose.t - gt.t).norm() << " mm";
	EXPECT_GT(e.confidence, 0.5f);
}

TEST_F(EndToEnd, BadBoxesGiveNoPoseWithAReason)
{
	DepthImageMm depth(640, 480, 0.0f);
	PoseEstimator estimator;
	EstimatorConfig cfg;
	PoseEstimate outside = estimator.estimate(depth.view(), kKinect, PixelBox{700, 10, 50, 50}, *model_, cfg);
	EXPECT_FALSE(outside.found);
	EXPECT_STREQ(outside.reason, "box outside the image");
	PoseEstimate empty = estimator.estimate(depth.view(), kKinect, PixelBox{10, 10, 0, 50}, *model_, cfg);
	EXPECT_FALSE(empty.found);
	EXPECT_STREQ(empty.reason, "empty box");
	PoseEstimate sparse = estimator.estimate(depth.view(), kKinect, PixelBox{10, 10, 50, 50}, *model_, cfg);
	EXPECT_FALSE(sparse.found);
	EXPECT_STREQ(sparse.reason, "too few valid depth pixels in the box");
}

TEST_F(EndToEnd, TrainingIsDeterministicFromTheSeed)
{
	Trained again = trainSmall(11);
	ForestStorage a(trained_->forest, TemplateEncoding::kUint8), b(again.forest, TemplateEncoding::kUint8);
	ASSERT_TRUE(saveModelFile(*dir_ / "a.ihf", trained_->params, trained_->mesh, a.view()).ok());
	ASSERT_TRUE(saveModelFile(*dir_ / "b.ihf", again.params, again.mesh, b.view()).ok());
	EXPECT_EQ(readAll(*dir_ / "a.ihf"), readAll(*dir_ / "b.ihf"));
}

} // namespace
} // namespace ihf
