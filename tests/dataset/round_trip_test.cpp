// SPDX-License-Identifier: MIT
// Every BOP file type written to a temporary folder and read back.

#include <random>

#include <gtest/gtest.h>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "tests/common/test_paths.h"
#include "tests/dataset/dataset_test_util.h"

namespace ihf {
namespace {

using test::posesEqual;
using test::relNear;

class RoundTrip : public ::testing::Test
{
protected:
	std::mt19937 rng_{1234};

	double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
	int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

	Pose randomPose()
	{
		Eigen::Quaterniond q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
		q.normalize();
		Pose p;
		p.R = q.toRotationMatrix();
		p.t = {uniform(-300, 300), uniform(-300, 300), uniform(300, 2000)};
		return p;
	}

	BopCamera randomCamera()
	{
		BopCamera cam;
		cam.intrinsics = {uniform(400, 700), uniform(400, 700), uniform(300, 340),
				  uniform(220, 260), 640, 480};
		cam.depthScale = 0.1;
		return cam;
	}

	std::map<int, ModelInfo> randomModelsInfo()
	{
		std::map<int, ModelInfo> info;
		for (int id : {1, 2, 10, 30}) {
			ModelInfo m;
			m.objId = id;
			m.diameter = uniform(50, 300);
			m.min = {uniform(-100, 0), uniform(-100, 0), uniform(-100, 0)};
			m.size = {uniform(10, 200), uniform(10, 200), uniform(10, 200)};
			info[id] = m;
		}
		info[2].symmetriesDiscrete = {randomPose(), randomPose()};
		info[10].hasContinuousSymmetry = true;
		info[10].symmetriesContinuous = {{{0, 0, 1}, {0.5, -0.25, 0}}};
		info[30].hasContinuousSymmetry = true; // flag without an axis list
		return info;
	}

	std::map<int, std::vector<GtInstance>> randomGt()
	{
		std::map<int, std::vector<GtInstance>> gt;
		for (int im : {0, 2, 10, 100}) {
			int n = im == 100 ? 0 : integer(1, 4); // also an image with no instance
			auto &list = gt[im];
			for (int i = 0; i < n; ++i)
				list.push_back({integer(1, 30), randomPose()});
		}
		return gt;
	}

	std::map<int, std::vector<GtInfo>> gtInfoFor(const std::map<int, std::vector<GtInstance>> &gt)
	{
		std::map<int, std::vector<GtInfo>> info;
		for (const auto &[im, list] : gt) {
			auto &out = info[im];
			for (size_t i = 0; i < list.size(); ++i) {
				GtInfo g;
				g.bboxObj = {integer(-5, 600), integer(0, 400), integer(1, 100), integer(1, 100)};
				g.bboxVisib = {integer(0, 600), integer(0, 400), integer(0, 100), integer(0, 100)};
				g.pxCountAll = integer(0, 9000);
				g.pxCountValid = integer(0, 9000);
				g.pxCountVisib = integer(0, 9000);
				g.visibFract = uniform(0, 1);
				out.push_back(g);
			}
		}
		return info;
	}
};

void expectSameGt(const std::map<int, std::vector<GtInstance>> &a,
		  const std::map<int, std::vector<GtInstance>> &b)
{
	ASSERT_EQ(a.size(), b.size());
	for (const auto &[im, list] : a) {
		ASSERT_TRUE(b.count(im)) << "image " << im;
		ASSERT_EQ(list.size(), b.at(im).size()) << "image " << im;
		for (size_t i = 0; i < list.size(); ++i) {
			EXPECT_EQ(list[i].objId, b.at(im)[i].objId);
			EXPECT_TRUE(posesEqual(list[i].pose, b.at(im)[i].pose)) << "image " << im << " #" << i;
		}
	}
}

void expectSameGtInfo(const std::map<int, std::vector<GtInfo>> &a,
		      const std::map<int, std::vector<GtInfo>> &b)
{
	ASSERT_EQ(a.size(), b.size());
	for (const auto &[im, list] : a) {
		ASSERT_EQ(list.size(), b.at(im).size()) << "image " << im;
		for (size_t i = 0; i < list.size(); ++i) {
			const GtInfo &x = list[i], &y = b.at(im)[i];
			EXPECT_EQ(x.bboxObj, y.bboxObj);
			EXPECT_EQ(x.bboxVisib, y.bboxVisib);
			EXPECT_EQ(x.pxCountAll, y.pxCountAll);
			EXPECT_EQ(x.pxCountValid, y.pxCountValid);
			EXPECT_EQ(x.pxCountVisib, y.pxCountVisib);
			EXPECT_TRUE(relNear(x.visibFract, y.visibFract));
		}
	}
}

TEST_F(RoundTrip, Camera)
{
	auto dir = test::freshTempDir("rt_camera");
	BopCamera cam = randomCamera();
	ASSERT_TRUE(writeBopCamera(dir / "camera.json", cam));
	auto back = readBopCamera(dir / "camera.json");
	ASSERT_TRUE(back) << back.error().message;
	EXPECT_TRUE(relNear(back->intrinsics.fx, cam.intrinsics.fx));
	EXPECT_TRUE(relNear(back->intrinsics.fy, cam.intrinsics.fy));
	EXPECT_TRUE(relNear(back->intrinsics.cx, cam.intrinsics.cx));
	EXPECT_TRUE(relNear(back->intrinsics.cy, cam.intrinsics.cy));
	EXPECT_EQ(back->intrinsics.width, 640);
	EXPECT_EQ(back->intrinsics.height, 480);
	EXPECT_TRUE(relNear(back->depthScale, 0.1));
}

TEST_F(RoundTrip, ModelsInfo)
{
	auto dir = test::freshTempDir("rt_models");
	auto info = randomModelsInfo();
	ASSERT_TRUE(writeModelsInfo(dir / "models_info.json", info));
	auto back = readModelsInfo(dir / "models_info.json");
	ASSERT_TRUE(back) << back.error().message;
	ASSERT_EQ(back->size(), info.size());
	for (const auto &[id, m] : info) {
		const ModelInfo &b = back->at(id);
		EXPECT_EQ(b.objId, id);
		EXPECT_TRUE(relNear(b.diameter, m.diameter));
		for (int i = 0; i < 3; ++i) {
			EXPECT_TRUE(relNear(b.min(i), m.min(i)));
			EXPECT_TRUE(relNear(b.size(i), m.size(i)));
		}
		ASSERT_EQ(b.symmetriesDiscrete.size(), m.symmetriesDiscrete.size());
		for (size_t s = 0; s < m.symmetriesDiscrete.size(); ++s)
			EXPECT_TRUE(posesEqual(b.symmetriesDiscrete[s], m.symmetriesDiscrete[s]));
		EXPECT_EQ(b.hasContinuousSymmetry, m.hasContinuousSymmetry) << "object " << id;
		ASSERT_EQ(b.symmetriesContinuous.size(), m.symmetriesContinuous.size());
		for (size_t s = 0; s < m.symmetriesContinuous.size(); ++s) {
			EXPECT_EQ(b.symmetriesContinuous[s].axis, m.symmetriesContinuous[s].axis);
			EXPECT_EQ(b.symmetriesContinuous[s].offset, m.symmetriesContinuous[s].offset);
		}
		EXPECT_EQ(b.symmetric(), id != 1);
	}
}

TEST_F(RoundTrip, SceneFiles)
{
	auto dir = test::freshTempDir("rt_scene");
	std::map<int, SceneCamera> cams;
	for (int im : {0, 2, 10, 100}) {
		BopCamera c = randomCamera();
		cams[im] = {c.intrinsics, uniform(0.05, 1.5)};
	}
	auto gt = randomGt();
	auto gtInfo = gtInfoFor(gt);

	ASSERT_TRUE(writeSceneCamera(dir / "scene_camera.json", cams));
	ASSERT_TRUE(writeSceneGt(dir / "scene_gt.json", gt));
	ASSERT_TRUE(writeSceneGtInfo(dir / "scene_gt_info.json", gtInfo));

	auto camsBack = readSceneCamera(dir / "scene_camera.json");
	ASSERT_TRUE(camsBack) << camsBack.error().message;
	ASSERT_EQ(camsBack->size(), cams.size());
	for (const auto &[im, c] : cams) {
		const SceneCamera &b = camsBack->at(im);
		EXPECT_TRUE(relNear(b.intrinsics.fx, c.intrinsics.fx));
		EXPECT_TRUE(relNear(b.intrinsics.fy, c.intrinsics.fy));
		EXPECT_TRUE(relNear(b.intrinsics.cx, c.intrinsics.cx));
		EXPECT_TRUE(relNear(b.intrinsics.cy, c.intrinsics.cy));
		EXPECT_TRUE(relNear(b.depthScale, c.depthScale));
	}

	auto gtBack = readSceneGt(dir / "scene_gt.json");
	ASSERT_TRUE(gtBack) << gtBack.error().message;
	expectSameGt(gt, *gtBack);

	auto infoBack = readSceneGtInfo(dir / "scene_gt_info.json");
	ASSERT_TRUE(infoBack) << infoBack.error().message;
	expectSameGtInfo(gtInfo, *infoBack);

	// Keys in numeric, not lexicographic, order; the writer is deterministic.
	std::string text = test::readText(dir / "scene_gt.json");
	size_t p2 = text.find("\"2\""), p10 = text.find("\"10\""), p100 = text.find("\"100\"");
	ASSERT_NE(p2, std::string::npos);
	ASSERT_NE(p100, std::string::npos);
	EXPECT_LT(text.find("\"0\""), p2);
	EXPECT_LT(p2, p10);
	EXPECT_LT(p10, p100);
	ASSERT_TRUE(writeSceneGt(dir / "again.json", gt));
	EXPECT_EQ(test::readText(dir / "again.json"), text);
}

TEST_F(RoundTrip, ResultsCsv)
{
	auto dir = test::freshTempDir("rt_csv");
	std::vector<ResultRow> rows;
	for (int i = 0; i < 50; ++i) {
		ResultRow r;
		r.sceneId = integer(0, 60);
		r.imId = integer(0, 2000);
		r.objId = integer(1, 30);
		r.score = uniform(0, 1);
		r.pose = randomPose();
		r.time = i % 5 == 0 ? -1 : uniform(0.001, 3);
		rows.push_back(r);
	}
	rows[3].pose.t.x() = 1e-300; // extremes of the number format
	rows[4].score = 123456789.123456789;
	const auto file = dir / "ihf_lmo-test.csv";
	ASSERT_TRUE(writeResultsCsv(file, rows));
	EXPECT_EQ(test::readText(file).rfind("scene_id,im_id,obj_id,score,R,t,time\n", 0), 0u);

	auto back = readResultsCsv(file);
	ASSERT_TRUE(back) << back.error().message;
	ASSERT_EQ(back->size(), rows.size());
	for (size_t i = 0; i < rows.size(); ++i) {
		const ResultRow &a = rows[i], &b = (*back)[i];
		EXPECT_EQ(a.sceneId, b.sceneId);
		EXPECT_EQ(a.imId, b.imId);
		EXPECT_EQ(a.objId, b.objId);
		// Shortest round-trip text: exactly the same doubles.
		EXPECT_EQ(a.score, b.score);
		EXPECT_EQ(a.time, b.time);
		EXPECT_EQ(a.pose.R, b.pose.R) << "row " << i;
		EXPECT_EQ(a.pose.t, b.pose.t) << "row " << i;
	}

	// A hand-written BOP line: R row-major, CRLF line ends tolerated.
	test::writeText(dir / "hand.csv", "scene_id,im_id,obj_id,score,R,t,time\r\n"
					  "2,3,5,0.9,1 2 3 4 5 6 7 8 9,10 20 30,-1\r\n");
	auto hand = readResultsCsv(dir / "hand.csv");
	ASSERT_TRUE(hand) << hand.error().message;
	ASSERT_EQ(hand->size(), 1u);
	EXPECT_EQ((*hand)[0].pose.R(0, 1), 2);
	EXPECT_EQ((*hand)[0].pose.R(1, 0), 4);
	EXPECT_EQ((*hand)[0].pose.t.z(), 30);
	EXPECT_EQ((*hand)[0].time, -1);
}

TEST_F(RoundTrip, Detections)
{
	auto dir = test::freshTempDir("rt_dets");
	std::vector<Detection> dets;
	for (int i = 0; i < 20; ++i) {
		Detection d;
		d.sceneId = integer(0, 60);
		d.imageId = integer(0, 2000);
		d.categoryId = integer(1, 30);
		d.score = uniform(0, 1);
		d.bbox = {uniform(0, 600), uniform(0, 400), uniform(1, 100), uniform(1, 100)};
		d.time = uniform(0, 1);
		dets.push_back(d);
	}
	ASSERT_TRUE(writeDetections(dir / "dets.json", dets));
	auto back = readDetections(dir / "dets.json");
	ASSERT_TRUE(back) << back.error().message;
	ASSERT_EQ(back->size(), dets.size());
	for (size_t i = 0; i < dets.size(); ++i) {
		EXPECT_EQ((*back)[i].sceneId, dets[i].sceneId);
		EXPECT_EQ((*back)[i].imageId, dets[i].imageId);
		EXPECT_EQ((*back)[i].categoryId, dets[i].categoryId);
		EXPECT_TRUE(relNear((*back)[i].score, dets[i].score));
		EXPECT_TRUE(relNear((*back)[i].time, dets[i].time));
		for (int k = 0; k < 4; ++k)
			EXPECT_TRUE(relNear((*back)[i].bbox[k], dets[i].bbox[k]));
	}
	ASSERT_TRUE(writeDetections(dir / "empty.json", {}));
	auto empty = readDetections(dir / "empty.json");
	ASSERT_TRUE(empty) << empty.error().message;
	EXPECT_TRUE(empty->empty());
}

TEST_F(RoundTrip, DepthPng)
{
	auto dir = test::freshTempDir("rt_png");
	// Odd size catches stride mistakes; extremes catch byte-order mistakes.
	DepthImage16 img(37, 23);
	for (uint16_t &v : img.pixels())
		v = static_cast<uint16_t>(integer(0, 65535));
	img.at(0, 0) = 0;
	img.at(1, 0) = 1;
	img.at(2, 0) = 255;
	img.at(3, 0) = 256;
	img.at(36, 22) = 65535;
	ASSERT_TRUE(writeDepthPng(dir / "d.png", img));

	// IHDR: width, height big-endian, bit depth 16, colour type 0 (grey).
	std::string bytes = test::readText(dir / "d.png");
	ASSERT_GT(bytes.size(), 26u);
	EXPECT_EQ(bytes.substr(12, 4), "IHDR");
	EXPECT_EQ(static_cast<uint8_t>(bytes[19]), 37);
	EXPECT_EQ(static_cast<uint8_t>(bytes[23]), 23);
	EXPECT_EQ(static_cast<uint8_t>(bytes[24]), 16);
	EXPECT_EQ(static_cast<uint8_t>(bytes[25]), 0);

	auto back = readDepthPng(dir / "d.png");
	ASSERT_TRUE(back) << back.error().message;
	ASSERT_EQ(back->width(), 37);
	ASSERT_EQ(back->height(), 23);
	for (int y = 0; y < 23; ++y)
		for (int x = 0; x < 37; ++x)
			ASSERT_EQ(back->at(x, y), img.at(x, y)) << x << "," << y;
}

TEST_F(RoundTrip, Png8Headers)
{
	auto dir = test::freshTempDir("rt_png8");
	std::vector<uint8_t> grey(5 * 4), rgb(5 * 4 * 3);
	for (auto &v : grey)
		v = static_cast<uint8_t>(integer(0, 255));
	for (auto &v : rgb)
		v = static_cast<uint8_t>(integer(0, 255));
	ASSERT_TRUE(writePng8(dir / "g.png", 5, 4, 1, grey.data()));
	ASSERT_TRUE(writePng8(dir / "c.png", 5, 4, 3, rgb.data()));
	std::string g = test::readText(dir / "g.png"), c = test::readText(dir / "c.png");
	EXPECT_EQ(static_cast<uint8_t>(g[24]), 8);
	EXPECT_EQ(static_cast<uint8_t>(g[25]), 0); // grey
	EXPECT_EQ(static_cast<uint8_t>(c[24]), 8);
	EXPECT_EQ(static_cast<uint8_t>(c[25]), 2); // RGB
	auto bad = writePng8(dir / "x.png", 5, 4, 2, grey.data());
	ASSERT_FALSE(bad);
	EXPECT_EQ(bad.error().code, Errc::kInvalidArgument);
	EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

TEST_F(RoundTrip, WholeDataset)
{
	auto root = test::freshTempDir("rt_dataset");
	BopCamera cam = randomCamera();
	auto info = randomModelsInfo();
	ASSERT_TRUE(createBopDataset(root, cam, info));

	// A fresh skeleton opens with the default split and no scenes.
	auto fresh = BopDataset::open(root);
	ASSERT_TRUE(fresh) << fresh.error().message;
	EXPECT_EQ(fresh->split(), "test");
	EXPECT_TRUE(fresh->sceneIds().empty());

	BopScene scene;
	scene.sceneId = 7;
	scene.gt = randomGt();
	scene.gtInfo = gtInfoFor(scene.gt);
	for (const auto &[im, list] : scene.gt)
		scene.cameras[im] = {cam.intrinsics, cam.depthScale};
	ASSERT_TRUE(fresh->saveScene(scene));
	DepthImage16 raw(640, 480);
	for (uint16_t &v : raw.pixels())
		v = static_cast<uint16_t>(integer(0, 20000));
	ASSERT_TRUE(writeDepthPng(fresh->depthPath(7, 10), raw));
	// Not a scene folder: ignored by sceneIds().
	std::filesystem::create_directories(root / "test" / "notes");

	auto ds = BopDataset::open(root);
	ASSERT_TRUE(ds) << ds.error().message;
	EXPECT_EQ(ds->sceneIds(), std::vector<int>{7});
	EXPECT_EQ(ds->modelsInfo().size(), info.size());
	EXPECT_TRUE(relNear(ds->camera().intrinsics.fx, cam.intrinsics.fx));

	auto back = ds->loadScene(7);
	ASSERT_TRUE(back) << back.error().message;
	expectSameGt(scene.gt, back->gt);
	expectSameGtInfo(scene.gtInfo, back->gtInfo);
	EXPECT_EQ(back->cameras.at(10).intrinsics.width, 640);

	auto mm = ds->loadDepthMm(7, 10, back->cameras.at(10).depthScale);
	ASSERT_TRUE(mm) << mm.error().message;
	for (int y = 0; y < 480; y += 7)
		for (int x = 0; x < 640; x += 5)
			ASSERT_FLOAT_EQ(mm->at(x, y), static_cast<float>(raw.at(x, y) * 0.1));
}

// modelPath's inverse, as `ihf train` names a model's object; anything but
// "obj_" and digits is no id.
TEST(ModelObjId, InvertsModelPathAndRejectsOtherNames)
{
	EXPECT_EQ(modelObjId("obj_000005"), 5);
	EXPECT_EQ(modelObjId("obj_12"), 12);
	EXPECT_EQ(modelObjId("obj_000000"), 0);
	for (const char *bad : {"obj_", "obj_-5", "obj_+5", "obj_5a", "obj_5.ply", "bunny", "xobj_5",
				"obj_99999999999"})
		EXPECT_EQ(modelObjId(bad), std::nullopt) << bad;
}

} // namespace
} // namespace ihf
