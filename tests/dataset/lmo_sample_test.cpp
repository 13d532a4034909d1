// SPDX-License-Identifier: MIT
// Reads the shared Occluded-LINEMOD sample. Expected values are copied from
// the JSON files and, for the depth frame, from an independent pure-Python
// zlib decode of the PNG (count, sum, median and single pixels).

#include <algorithm>
#include <cstdint>

#include <gtest/gtest.h>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "tests/common/test_paths.h"
#include "tests/dataset/dataset_test_util.h"

namespace ihf {
namespace {

using test::lmoDir;

TEST(LmoSample, Camera)
{
	auto cam = readBopCamera(lmoDir() / "camera.json");
	ASSERT_TRUE(cam) << cam.error().message;
	EXPECT_DOUBLE_EQ(cam->intrinsics.fx, 572.4114);
	EXPECT_DOUBLE_EQ(cam->intrinsics.fy, 573.57043);
	EXPECT_DOUBLE_EQ(cam->intrinsics.cx, 325.2611);
	EXPECT_DOUBLE_EQ(cam->intrinsics.cy, 242.04899);
	EXPECT_EQ(cam->intrinsics.width, 640);
	EXPECT_EQ(cam->intrinsics.height, 480);
	EXPECT_DOUBLE_EQ(cam->depthScale, 1.0);
}

TEST(LmoSample, ModelsInfo)
{
	auto info = readModelsInfo(lmoDir() / "models" / "models_info.json");
	ASSERT_TRUE(info) << info.error().message;
	std::vector<int> ids;
	for (const auto &[id, m] : *info) {
		ids.push_back(id);
		EXPECT_EQ(m.objId, id);
		EXPECT_EQ(m.symmetric(), id == 10 || id == 11) << "object " << id;
		EXPECT_FALSE(m.hasContinuousSymmetry);
	}
	EXPECT_EQ(ids, (std::vector<int>{1, 5, 6, 8, 9, 10, 11, 12}));

	const ModelInfo &ape = info->at(1);
	EXPECT_DOUBLE_EQ(ape.diameter, 102.099);
	EXPECT_DOUBLE_EQ(ape.min.x(), -37.9343);
	EXPECT_DOUBLE_EQ(ape.min.z(), -45.8845);
	EXPECT_DOUBLE_EQ(ape.size.y(), 77.5992);
	EXPECT_DOUBLE_EQ(info->at(12).size.z(), 90.8);

	// Row-major 4x4 with t in the last column.
	const ModelInfo &eggbox = info->at(10);
	ASSERT_EQ(eggbox.symmetriesDiscrete.size(), 1u);
	const Pose &s = eggbox.symmetriesDiscrete[0];
	EXPECT_DOUBLE_EQ(s.R(0, 0), -0.999964);
	EXPECT_DOUBLE_EQ(s.R(0, 1), -0.00333777);
	EXPECT_DOUBLE_EQ(s.R(1, 0), 0.00321462);
	EXPECT_DOUBLE_EQ(s.R(2, 1), 0.0158338);
	EXPECT_DOUBLE_EQ(s.t.x(), 0.232611);
	EXPECT_DOUBLE_EQ(s.t.y(), 0.694388);
	EXPECT_DOUBLE_EQ(s.t.z(), -0.0792063);
	ASSERT_EQ(info->at(11).symmetriesDiscrete.size(), 1u);
	EXPECT_DOUBLE_EQ(info->at(11).symmetriesDiscrete[0].t.x(), -0.262139);
}

TEST(LmoSample, OpenAndScene)
{
	auto ds = BopDataset::open(lmoDir());
	ASSERT_TRUE(ds) << ds.error().message;
	EXPECT_EQ(ds->split(), "test");
	EXPECT_EQ(ds->sceneIds(), std::vector<int>{2});
	EXPECT_EQ(ds->modelsInfo().size(), 8u);
	EXPECT_EQ(ds->depthPath(2, 3), lmoDir() / "test" / "000002" / "depth" / "000003.png");
	EXPECT_EQ(ds->modelPath(5), lmoDir() / "models" / "obj_000005.ply");

	auto scene = ds->loadScene(2);
	ASSERT_TRUE(scene) << scene.error().message;
	EXPECT_EQ(scene->sceneId, 2);
	ASSERT_EQ(scene->cameras.size(), 1u);
	const SceneCamera &cam = scene->cameras.at(3);
	EXPECT_DOUBLE_EQ(cam.intrinsics.fx, 572.4114);
	EXPECT_DOUBLE_EQ(cam.intrinsics.fy, 573.57043);
	EXPECT_DOUBLE_EQ(cam.intrinsics.cx, 325.2611);
	EXPECT_DOUBLE_EQ(cam.intrinsics.cy, 242.04899);
	EXPECT_EQ(cam.intrinsics.width, 640);
	EXPECT_EQ(cam.intrinsics.height, 480);
	EXPECT_DOUBLE_EQ(cam.depthScale, 1.0);

	ASSERT_EQ(scene->gt.size(), 1u);
	const auto &gt = scene->gt.at(3);
	ASSERT_EQ(gt.size(), 8u);
	std::vector<int> objIds;
	for (const GtInstance &g : gt)
		objIds.push_back(g.objId);
	EXPECT_EQ(objIds, (std::vector<int>{1, 5, 6, 8, 9, 10, 11, 12}));
	// cam_R_m2c is row-major.
	EXPECT_DOUBLE_EQ(gt[0].pose.R(0, 1), 0.47867615);
	EXPECT_DOUBLE_EQ(gt[0].pose.R(1, 0), 0.3746311);
	EXPECT_DOUBLE_EQ(gt[0].pose.R(2, 2), -0.84552592);
	EXPECT_DOUBLE_EQ(gt[0].pose.t.x(), 161.68945982);
	EXPECT_DOUBLE_EQ(gt[0].pose.t.z(), 1112.83112737);
	EXPECT_DOUBLE_EQ(gt[7].pose.t.y(), 120.607);
	// The sample's rotations are rounded/refined and not exactly orthonormal
	// (det up to 1.0029 for the driller); the reader passes them on unchanged.
	for (const GtInstance &g : gt)
		EXPECT_NEAR(g.pose.R.determinant(), 1.0, 5e-3) << "object " << g.objId;
	EXPECT_NEAR(gt[3].pose.R.determinant(), 1.0028881013850846, 1e-12);

	ASSERT_EQ(scene->gtInfo.at(3).size(), 8u);
	const GtInfo &i0 = scene->gtInfo.at(3)[0];
	EXPECT_EQ(i0.bboxObj, (std::array<int, 4>{388, 164, 34, 45}));
	EXPECT_EQ(i0.bboxVisib, (std::array<int, 4>{401, 164, 20, 33}));
	EXPECT_EQ(i0.pxCountAll, 1127);
	EXPECT_EQ(i0.pxCountValid, 1105);
	EXPECT_EQ(i0.pxCountVisib, 225);
	EXPECT_DOUBLE_EQ(i0.visibFract, 0.19964507542147295);
}

TEST(LmoSample, DepthFrame)
{
	auto raw = readDepthPng(lmoDir() / "test" / "000002" / "depth" / "000003.png");
	ASSERT_TRUE(raw) << raw.error().message;
	ASSERT_EQ(raw->width(), 640);
	ASSERT_EQ(raw->height(), 480);
	EXPECT_EQ(raw->at(0, 0), 0);
	EXPECT_EQ(raw->at(320, 240), 1004);
	EXPECT_EQ(raw->at(100, 100), 1227);
	EXPECT_EQ(raw->at(400, 180), 925);
	EXPECT_EQ(raw->at(630, 470), 1572);

	uint64_t sum = 0;
	std::vector<uint16_t> nonZero;
	for (uint16_t v : raw->pixels()) {
		sum += v;
		if (v)
			nonZero.push_back(v);
	}
	EXPECT_EQ(sum, 342493551u);
	ASSERT_EQ(nonZero.size(), 291323u);
	std::nth_element(nonZero.begin(), nonZero.begin() + nonZero.size() / 2, nonZero.end());
	uint16_t median = nonZero[nonZero.size() / 2];
	EXPECT_EQ(median, 1123);
	EXPECT_GE(median, 500);
	EXPECT_LE(median, 1500);
}

// Depth and GT agree: at the projected centre of each well-visible object the
// sensor sees its front surface, between t.z - diameter/2 and t.z.
TEST(LmoSample, DepthMatchesGroundTruth)
{
	auto ds = BopDataset::open(lmoDir());
	ASSERT_TRUE(ds) << ds.error().message;
	auto scene = ds->loadScene(2);
	ASSERT_TRUE(scene) << scene.error().message;
	const SceneCamera &cam = scene->cameras.at(3);
	auto depth = ds->loadDepthMm(2, 3, cam.depthScale);
	ASSERT_TRUE(depth) << depth.error().message;

	int checked = 0;
	for (size_t i = 0; i < scene->gt.at(3).size(); ++i) {
		const GtInstance &g = scene->gt.at(3)[i];
		if (scene->gtInfo.at(3)[i].visibFract < 0.75)
			continue;
		Eigen::Vector2d uv = cam.intrinsics.project(g.pose.t);
		int u = static_cast<int>(std::lround(uv.x()));
		int v = static_cast<int>(std::lround(uv.y()));
		std::vector<float> window;
		for (int y = v - 2; y <= v + 2; ++y)
			for (int x = u - 2; x <= u + 2; ++x)
				if (depth->at(x, y) > 0)
					window.push_back(depth->at(x, y));
		ASSERT_FALSE(window.empty()) << "object " << g.objId;
		std::nth_element(window.begin(), window.begin() + window.size() / 2, window.end());
		float z = window[window.size() / 2];
		double radius = ds->modelsInfo().at(g.objId).diameter / 2;
		EXPECT_LE(z, g.pose.t.z() + 5) << "object " << g.objId;
		EXPECT_GE(z, g.pose.t.z() - radius) << "object " << g.objId;
		++checked;
	}
	EXPECT_EQ(checked, 6); // objects 5, 6, 8, 9, 11, 12
}

TEST(LmoSample, DepthScaleApplied)
{
	auto ds = BopDataset::open(lmoDir());
	ASSERT_TRUE(ds) << ds.error().message;
	auto mm = ds->loadDepthMm(2, 3, 0.1);
	ASSERT_TRUE(mm) << mm.error().message;
	EXPECT_FLOAT_EQ(mm->at(320, 240), 100.4f);
	EXPECT_FLOAT_EQ(mm->at(0, 0), 0.0f);
}

TEST(LmoSample, Model)
{
	auto ds = BopDataset::open(lmoDir());
	ASSERT_TRUE(ds) << ds.error().message;
	auto mesh = ds->loadModel(1);
	ASSERT_TRUE(mesh) << mesh.error().message;
	ASSERT_FALSE(mesh->vertices.empty());
	ASSERT_FALSE(mesh->faces.empty());
	// The mesh's bounding box is what models_info.json describes.
	Aabb box = boundingBox(*mesh);
	const ModelInfo &info = ds->modelsInfo().at(1);
	for (int i = 0; i < 3; ++i) {
		EXPECT_NEAR(box.min(i), info.min(i), 0.01) << "axis " << i;
		EXPECT_NEAR(box.size()(i), info.size(i), 0.01) << "axis " << i;
	}
}

TEST(LmoSample, MissingFrameAndModel)
{
	auto ds = BopDataset::open(lmoDir());
	ASSERT_TRUE(ds) << ds.error().message;
	auto depth = ds->loadDepthMm(2, 99, 1.0);
	ASSERT_FALSE(depth);
	EXPECT_EQ(depth.error().code, Errc::kNotFound);
	EXPECT_NE(depth.error().message.find(ds->depthPath(2, 99).string()), std::string::npos)
		<< depth.error().message;
	EXPECT_NE(depth.error().message.find("000099.png"), std::string::npos);

	auto model = ds->loadModel(2);
	ASSERT_FALSE(model);
	EXPECT_EQ(model.error().code, Errc::kNotFound);
	EXPECT_NE(model.error().message.find("obj_000002.ply"), std::string::npos);

	auto scene = ds->loadScene(7);
	ASSERT_FALSE(scene);
	EXPECT_EQ(scene.error().code, Errc::kNotFound);
	EXPECT_NE(scene.error().message.find("000007"), std::string::npos);

	auto split = BopDataset::open(lmoDir(), "train");
	ASSERT_FALSE(split);
	EXPECT_EQ(split.error().code, Errc::kNotFound);
	EXPECT_NE(split.error().message.find("train"), std::string::npos);
}

} // namespace
} // namespace ihf
