// SPDX-License-Identifier: MIT
// Malformed and mistyped inputs: every error names the file and the JSON
// field or CSV line:column at fault.

#include <gtest/gtest.h>
#include <zlib.h>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "tests/common/test_paths.h"
#include "tests/dataset/dataset_test_util.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

template<typename T>
std::string errorOf(const Expected<T> &r)
{
	return r ? std::string("(no error)") : std::string(r.error().message);
}

bool contains(const std::string &s, const std::string &part)
{
	return s.find(part) != std::string::npos;
}

const char *kGoodInstance =
	R"({"cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [1, 2, 3], "obj_id": 5})";

TEST(BadInput, TruncatedJson)
{
	auto dir = test::freshTempDir("bad_truncated");
	std::string text = test::readText(test::lmoDir() / "test" / "000002" / "scene_gt.json");
	ASSERT_GT(text.size(), 1000u);
	test::writeText(dir / "scene_gt.json", text.substr(0, text.size() / 2));
	auto r = readSceneGt(dir / "scene_gt.json");
	ASSERT_FALSE(r);
	EXPECT_EQ(r.error().code, Errc::kParse);
	const std::string &m = r.error().message;
	EXPECT_TRUE(contains(m, (dir / "scene_gt.json").string())) << m;
	EXPECT_TRUE(contains(m, "malformed JSON (byte ")) << m;
	EXPECT_TRUE(contains(m, "line ")) << m;
}

TEST(BadInput, WrongTypedFields)
{
	auto dir = test::freshTempDir("bad_types");
	const fs::path gt = dir / "scene_gt.json";
	const std::string prefix = gt.string() + ": ";

	test::writeText(gt, std::string(R"({"3": [)") + kGoodInstance +
				    R"(, {"cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [1, 2], "obj_id": 5}]})");
	EXPECT_EQ(errorOf(readSceneGt(gt)), prefix + R"("3"[1].cam_t_m2c: expected 3 numbers, got 2)");

	test::writeText(gt, std::string(R"({"3": [)") + kGoodInstance +
				    R"(, {"cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": "abc", "obj_id": 5}]})");
	EXPECT_EQ(errorOf(readSceneGt(gt)),
		  prefix + R"("3"[1].cam_t_m2c: expected a list of 3 numbers, got string)");

	test::writeText(gt, R"({"3": [{"cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, "x", 1], "cam_t_m2c": [1, 2, 3], "obj_id": 5}]})");
	EXPECT_EQ(errorOf(readSceneGt(gt)), prefix + R"("3"[0].cam_R_m2c[7]: expected a number, got string)");

	test::writeText(gt, R"({"3": [{"cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [1, 2, 3], "obj_id": 5.5}]})");
	EXPECT_EQ(errorOf(readSceneGt(gt)), prefix + R"("3"[0].obj_id: expected an integer, got number 5.5)");

	// An integral float is still an integer (some tools write ids as 5.0).
	test::writeText(gt, R"({"3": [{"cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [1, 2, 3], "obj_id": 5.0}]})");
	auto lenient = readSceneGt(gt);
	ASSERT_TRUE(lenient) << lenient.error().message;
	EXPECT_EQ(lenient->at(3)[0].objId, 5);

	test::writeText(gt, R"({"3": [{"cam_t_m2c": [1, 2, 3], "obj_id": 5}]})");
	EXPECT_EQ(errorOf(readSceneGt(gt)), prefix + R"("3"[0].cam_R_m2c: missing field)");

	test::writeText(gt, std::string(R"({"three": [)") + kGoodInstance + "]}");
	EXPECT_EQ(errorOf(readSceneGt(gt)), prefix + R"("three": expected a non-negative integer id as key)");

	test::writeText(gt, R"({"3": {"obj_id": 5}})");
	EXPECT_EQ(errorOf(readSceneGt(gt)), prefix + R"("3": expected a list, got object)");

	const fs::path cam = dir / "camera.json";
	test::writeText(cam, R"({"cx": 325.2611, "cy": 242.04899, "depth_scale": 1.0, "fx": "572.4", "fy": 573.57043, "height": 480, "width": 640})");
	EXPECT_EQ(errorOf(readBopCamera(cam)), cam.string() + ": fx: expected a number, got string");
	test::writeText(cam, R"({"cx": 325.2611, "cy": 242.04899, "fx": 572.4, "fy": 573.57043, "height": 480})");
	EXPECT_EQ(errorOf(readBopCamera(cam)), cam.string() + ": width: missing field");

	const fs::path sc = dir / "scene_camera.json";
	test::writeText(sc, R"({"3": {"cam_K": [572.4, 0, 325.2, 0, null, 242.0, 0, 0, 1], "depth_scale": 1.0}})");
	EXPECT_EQ(errorOf(readSceneCamera(sc)), sc.string() + R"(: "3".cam_K[4]: expected a number, got null)");
	// Extra fields (cam_R_w2c, cam_t_w2c) are tolerated.
	test::writeText(sc, R"({"3": {"cam_K": [572.4, 0, 325.2, 0, 573.5, 242.0, 0, 0, 1], "cam_R_w2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_w2c": [0, 0, 0], "depth_scale": 0.1}})");
	auto cams = readSceneCamera(sc);
	ASSERT_TRUE(cams) << cams.error().message;
	EXPECT_DOUBLE_EQ(cams->at(3).intrinsics.fy, 573.5);
	EXPECT_DOUBLE_EQ(cams->at(3).depthScale, 0.1);

	const fs::path mi = dir / "models_info.json";
	test::writeText(mi, R"({"10": {"diameter": 164.6, "min_x": -75, "min_y": -53, "min_z": -34, "size_x": 150, "size_y": 107, "size_z": 69, "symmetries_discrete": [[-1, 0, 0, 0.2, 0, -1, 0, 0.7, 0, 0, 1, 0, 0, 0, 1]]}})");
	EXPECT_EQ(errorOf(readModelsInfo(mi)),
		  mi.string() + R"(: "10".symmetries_discrete[0]: expected 16 numbers, got 15)");

	const fs::path info = dir / "scene_gt_info.json";
	test::writeText(info, R"({"3": [{"bbox_obj": [1, 2, 3, 4], "bbox_visib": [1, 2, 3.5, 4], "px_count_all": 1, "px_count_valid": 1, "px_count_visib": 1, "visib_fract": 1.0}]})");
	EXPECT_EQ(errorOf(readSceneGtInfo(info)),
		  info.string() + R"(: "3"[0].bbox_visib[2]: expected an integer, got number 3.5)");

	const fs::path dets = dir / "dets.json";
	test::writeText(dets, R"([{"scene_id": 2, "image_id": 3, "category_id": 5, "score": 0.5, "bbox": [1, 2, 3, 4], "time": 0.1}, {"scene_id": 2, "image_id": 3, "category_id": 5, "score": "high", "bbox": [1, 2, 3, 4]}])");
	EXPECT_EQ(errorOf(readDetections(dets)), dets.string() + ": [1].score: expected a number, got string");
	// A box no int pixel box can hold.
	test::writeText(dets, R"([{"scene_id": 2, "image_id": 3, "category_id": 5, "score": 0.5, "bbox": [1, 2, 1e300, 4]}])");
	EXPECT_EQ(errorOf(readDetections(dets)),
		  dets.string() + ": [0].bbox[2]: must lie within +-1e6 pixels, got " + std::to_string(1e300));

	EXPECT_EQ(readSceneGt(dir / "absent.json").error().code, Errc::kNotFound);
}

TEST(BadInput, GtInfoCountMismatch)
{
	auto root = test::freshTempDir("bad_gtinfo");
	fs::copy_file(test::lmoDir() / "camera.json", root / "camera.json");
	const fs::path scene = root / "test" / "000002";
	fs::create_directories(scene);
	fs::copy_file(test::lmoDir() / "test" / "000002" / "scene_camera.json", scene / "scene_camera.json");
	fs::copy_file(test::lmoDir() / "test" / "000002" / "scene_gt.json", scene / "scene_gt.json");
	auto info = readSceneGtInfo(test::lmoDir() / "test" / "000002" / "scene_gt_info.json");
	ASSERT_TRUE(info) << info.error().message;
	info->at(3).pop_back();
	ASSERT_TRUE(writeSceneGtInfo(scene / "scene_gt_info.json", *info));

	auto ds = BopDataset::open(root);
	ASSERT_TRUE(ds) << ds.error().message;
	EXPECT_FALSE(fs::exists(root / "models")); // models_info.json is optional
	auto r = ds->loadScene(2);
	ASSERT_FALSE(r);
	EXPECT_EQ(r.error().code, Errc::kCorrupt);
	EXPECT_TRUE(contains(r.error().message, (scene / "scene_gt_info.json").string() +
							": \"3\": 7 entries but"))
		<< r.error().message;

	// The same mismatch is refused on the way out.
	BopScene bad;
	bad.sceneId = 5;
	bad.gt = *readSceneGt(scene / "scene_gt.json");
	bad.gtInfo = *info;
	EXPECT_FALSE(ds->saveScene(bad));
	EXPECT_FALSE(fs::exists(ds->sceneDir(5)));

	// Without scene_gt_info.json the scene loads.
	fs::remove(scene / "scene_gt_info.json");
	auto ok = ds->loadScene(2);
	ASSERT_TRUE(ok) << ok.error().message;
	EXPECT_TRUE(ok->gtInfo.empty());
	EXPECT_EQ(ok->gt.at(3).size(), 8u);
}

// Estimation reads a scene's cameras alone; the ground truth is a separate
// step that a scene without scene_gt.json fails, naming the file, without
// touching the cameras. scene_gt_info.json without px_count_valid loads.
TEST(BadInput, SceneWithoutGroundTruth)
{
	auto root = test::freshTempDir("no_gt");
	fs::copy_file(test::lmoDir() / "camera.json", root / "camera.json");
	const fs::path scene = root / "test" / "000002";
	fs::create_directories(scene);
	fs::copy_file(test::lmoDir() / "test" / "000002" / "scene_camera.json", scene / "scene_camera.json");
	auto ds = BopDataset::open(root);
	ASSERT_TRUE(ds) << ds.error().message;

	auto cams = ds->loadSceneCameras(2);
	ASSERT_TRUE(cams) << cams.error().message;
	ASSERT_EQ(cams->cameras.size(), 1u);
	EXPECT_EQ(cams->cameras.at(3).intrinsics.width, 640);
	EXPECT_TRUE(cams->gt.empty());
	Status gt = ds->loadSceneGt(*cams);
	ASSERT_FALSE(gt);
	EXPECT_EQ(gt.error().code, Errc::kNotFound);
	EXPECT_TRUE(contains(gt.error().message, (scene / "scene_gt.json").string())) << gt.error().message;
	EXPECT_EQ(cams->cameras.size(), 1u);
	EXPECT_FALSE(ds->loadScene(2));

	test::writeText(scene / "scene_gt.json", std::string(R"({"3": [)") + kGoodInstance + "]}");
	test::writeText(scene / "scene_gt_info.json",
			R"({"3": [{"bbox_obj": [1, 2, 3, 4], "bbox_visib": [1, 2, 3, 4], "px_count_all": 9, "px_count_visib": 7, "visib_fract": 0.7}]})");
	gt = ds->loadSceneGt(*cams);
	ASSERT_TRUE(gt) << gt.error().message;
	ASSERT_EQ(cams->gtInfo.at(3).size(), 1u);
	EXPECT_EQ(cams->gtInfo.at(3)[0].pxCountValid, -1);
	EXPECT_EQ(cams->gtInfo.at(3)[0].pxCountVisib, 7);
	// Written back without the field it did not have.
	ASSERT_TRUE(writeSceneGtInfo(scene / "scene_gt_info.json", cams->gtInfo));
	EXPECT_FALSE(contains(test::readText(scene / "scene_gt_info.json"), "px_count_valid"));
}

TEST(BadInput, MissingCamera)
{
	auto root = test::freshTempDir("bad_nocamera");
	auto r = BopDataset::open(root);
	ASSERT_FALSE(r);
	EXPECT_EQ(r.error().code, Errc::kNotFound);
	EXPECT_TRUE(contains(r.error().message, (root / "camera.json").string())) << r.error().message;
	EXPECT_EQ(BopDataset::open(root / "nowhere").error().code, Errc::kNotFound);
}

TEST(BadInput, ResultsCsv)
{
	auto dir = test::freshTempDir("bad_csv");
	const fs::path f = dir / "res.csv";
	const std::string header = "scene_id,im_id,obj_id,score,R,t,time\n";
	const std::string good = "2,3,5,0.9,1 0 0 0 1 0 0 0 1,10 20 30,0.5\n";

	test::writeText(f, header + good + "2,3,5,0.9,1 0 0 0 1 0 0 0 1,10 20 30\n");
	EXPECT_EQ(errorOf(readResultsCsv(f)),
		  f.string() + ":3:1: expected 7 columns (scene_id,im_id,obj_id,score,R,t,time), got 6");

	test::writeText(f, header + "2,3,5,0.9,1 0 0 0 1 0 0 0,10 20 30,0.5\n");
	EXPECT_EQ(errorOf(readResultsCsv(f)), f.string() + ":2:11: column 5 (R): expected 9 numbers, got 8");

	test::writeText(f, header + good + good + "2,3,x5,0.9,1 0 0 0 1 0 0 0 1,10 20 30,0.5\n");
	EXPECT_EQ(errorOf(readResultsCsv(f)),
		  f.string() + ":4:5: column 3 (obj_id): expected an integer, got \"x5\"");

	test::writeText(f, header + "2,3,5,0.9,1 0 0 0 1 0 0 0 1,10 2o 30,0.5\n");
	EXPECT_EQ(errorOf(readResultsCsv(f)),
		  f.string() + ":2:29: column 6 (t): value 2: expected a number, got \"2o\"");

	test::writeText(f, good);
	EXPECT_TRUE(contains(errorOf(readResultsCsv(f)), f.string() + ":1:1: expected header"));

	test::writeText(f, "");
	EXPECT_TRUE(contains(errorOf(readResultsCsv(f)), f.string() + ":1:1: empty file"));

	test::writeText(f, header);
	auto empty = readResultsCsv(f);
	ASSERT_TRUE(empty) << empty.error().message;
	EXPECT_TRUE(empty->empty());
}

// PNG chunks and headers that claim far more than the file holds (inputs
// found by tests/fuzz/fuzz_depth_png): a text chunk claiming 2 GB made
// libpng allocate it, and a 32768 x 32768 header the 2 GiB image, before
// any data was read. Both are refused with an error naming the file.
TEST(BadInput, DepthPngClaimingHugeSizes)
{
	auto dir = test::freshTempDir("png_claims");
	auto u32 = [](std::string &s, uint32_t v) {
		for (int shift : {24, 16, 8, 0})
			s += static_cast<char>((v >> shift) & 0xff);
	};
	// Signature, IHDR (CRC checked by libpng), then a chunk header.
	auto png = [&](uint32_t w, uint32_t h) {
		std::string s = "\x89PNG\r\n\x1a\n";
		std::string ihdr = "IHDR";
		u32(ihdr, w);
		u32(ihdr, h);
		ihdr += std::string("\x10\x00\x00\x00\x00", 5); // 16-bit grey, no interlace
		u32(s, 13);
		s += ihdr;
		u32(s, static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef *>(ihdr.data()), ihdr.size())));
		return s;
	};
	std::string chunk = png(1, 1);
	u32(chunk, 0x7ffffff0u);
	chunk += "tEXtabcd";
	test::writeText(dir / "chunk.png", chunk);
	auto c = readDepthPng(dir / "chunk.png");
	ASSERT_FALSE(c);
	EXPECT_EQ(c.error().code, Errc::kCorrupt);
	EXPECT_TRUE(contains(c.error().message, (dir / "chunk.png").string() + ": bad PNG")) << c.error().message;

	std::string wide = png(32768, 32768);
	u32(wide, 12);
	wide += "IDAT" + std::string(16, '\0');
	test::writeText(dir / "wide.png", wide);
	auto w = readDepthPng(dir / "wide.png");
	ASSERT_FALSE(w);
	EXPECT_EQ(w.error().code, Errc::kCorrupt);
	EXPECT_EQ(w.error().message, (dir / "wide.png").string() + ": header claims a 32768x32768 image, more than "
								   "the file's " + std::to_string(wide.size()) +
					     " bytes can hold (truncated?)");
	// Past libpng's own limit on a side.
	std::string huge = png(40000, 2);
	u32(huge, 0);
	huge += "IEND";
	test::writeText(dir / "huge.png", huge);
	auto h = readDepthPng(dir / "huge.png");
	ASSERT_FALSE(h);
	EXPECT_TRUE(contains(h.error().message, (dir / "huge.png").string() + ": bad PNG header")) << h.error().message;
}

TEST(BadInput, DepthPngNot16Bit)
{
	auto dir = test::freshTempDir("bad_png");
	std::vector<uint8_t> grey(8 * 6, 100), rgb(8 * 6 * 3, 50);
	ASSERT_TRUE(writePng8(dir / "grey.png", 8, 6, 1, grey.data()));
	ASSERT_TRUE(writePng8(dir / "rgb.png", 8, 6, 3, rgb.data()));

	auto g = readDepthPng(dir / "grey.png");
	ASSERT_FALSE(g);
	EXPECT_EQ(g.error().code, Errc::kUnsupported);
	EXPECT_EQ(g.error().message,
		  (dir / "grey.png").string() + ": not a 16-bit single-channel PNG (it is 8-bit grey)");
	auto c = readDepthPng(dir / "rgb.png");
	ASSERT_FALSE(c);
	EXPECT_EQ(c.error().message,
		  (dir / "rgb.png").string() + ": not a 16-bit single-channel PNG (it is 8-bit RGB)");
	// The sample's colour image, too.
	auto lmoRgb = readDepthPng(test::lmoDir() / "test" / "000002" / "rgb" / "000003.png");
	ASSERT_FALSE(lmoRgb);
	EXPECT_EQ(lmoRgb.error().code, Errc::kUnsupported);

	test::writeText(dir / "text.png", "this is not a picture");
	auto t = readDepthPng(dir / "text.png");
	ASSERT_FALSE(t);
	EXPECT_EQ(t.error().message, (dir / "text.png").string() + ": not a PNG file");

	// A depth frame cut in half: decoding fails cleanly.
	std::string full = test::readText(test::lmoDir() / "test" / "000002" / "depth" / "000003.png");
	test::writeText(dir / "cut.png", full.substr(0, full.size() / 2));
	auto cut = readDepthPng(dir / "cut.png");
	ASSERT_FALSE(cut);
	EXPECT_EQ(cut.error().code, Errc::kCorrupt);
	EXPECT_TRUE(contains(cut.error().message, (dir / "cut.png").string() + ": bad PNG data"))
		<< cut.error().message;

	auto missing = readDepthPng(dir / "000001.png");
	ASSERT_FALSE(missing);
	EXPECT_EQ(missing.error().code, Errc::kNotFound);
	EXPECT_TRUE(contains(missing.error().message, (dir / "000001.png").string()));
}

} // namespace
} // namespace ihf
