// SPDX-License-Identifier: MIT
// `ihf record` end to end: BOP datasets (the real LM-O frame and a small
// generated one) and frame sources to .rec, `ihf record info`, usage errors.

#include <gtest/gtest.h>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "drivers/recording_reader.h"
#include "tests/common/test_paths.h"
#include "tests/drivers/recording_test_util.h"

namespace ihf::test {
namespace {

namespace fs = std::filesystem;

TEST(RecordCli, FromBopLmoFrameEqualsThePng)
{
	const fs::path out = freshTempDir("record_lmo") / "lmo.rec";
	CommandResult r = runIhf("record --from-bop " + lmoDir().string() +
				 " --split test --scene 2 --out " + out.string());
	ASSERT_EQ(r.exitCode, 0) << r.output;

	auto reader = RecordingReader::open(out);
	ASSERT_TRUE(reader.ok()) << reader.error().message;
	ASSERT_EQ(reader->frameCount(), 1u);
	EXPECT_EQ(reader->entry(0).frameIndex, 3u); // the BOP image id
	const auto &h = reader->header();
	// scene_camera.json of LM-O test/000002, image 3.
	EXPECT_EQ(h.intrinsics.fx, 572.4114);
	EXPECT_EQ(h.intrinsics.fy, 573.57043);
	EXPECT_EQ(h.intrinsics.cx, 325.2611);
	EXPECT_EQ(h.intrinsics.cy, 242.04899);
	EXPECT_EQ(h.intrinsics.width, 640);
	EXPECT_EQ(h.intrinsics.height, 480);
	EXPECT_EQ(h.depthScale, 1.0);
	EXPECT_EQ(h.sensorId, "bop:lmo/test/2");

	auto png = readDepthPng(lmoDir() / "test" / "000002" / "depth" / "000003.png");
	ASSERT_TRUE(png.ok());
	DepthImage16 frame(640, 480);
	recording::FrameRecord rec;
	ASSERT_EQ(*reader->read(0, rec, frame.view()), FrameCheck::kOk);
	EXPECT_EQ(depthDifference(frame.view(), *png), "");
	size_t nonZero = 0;
	for (uint16_t v : frame.pixels())
		nonZero += v != 0;
	EXPECT_GT(nonZero, 100000u); // a real depth map, not an empty one

	// One scene: --scene may be left out; info summarises and checks it.
	const fs::path again = out.parent_path() / "again.rec";
	r = runIhf("record --from-bop " + lmoDir().string() + " --compress --out " + again.string());
	ASSERT_EQ(r.exitCode, 0) << r.output;
	r = runIhf("record info " + again.string());
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("frames        1\n"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("640 x 480"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("checked       1 ok, 0 corrupt; 1 zlib, 0 raw"), std::string::npos) << r.output;
}

// A three-image scene with depth_scale 0.1 in scene_camera.json.
fs::path makeBopScene(const fs::path &root, double imageTwoFx)
{
	BopCamera cam;
	cam.intrinsics = CameraIntrinsics{500, 501, 31.5, 23.5, 64, 48};
	cam.depthScale = 1.0;
	EXPECT_TRUE(createBopDataset(root, cam, {}).ok());
	auto ds = BopDataset::open(root); // a fresh skeleton: split "test"
	if (!ds.ok()) {
		ADD_FAILURE() << ds.error().message;
		return root;
	}
	BopScene scene;
	scene.sceneId = 7;
	for (int im : {4, 5, 9}) {
		SceneCamera sc;
		sc.intrinsics = CameraIntrinsics{im == 5 ? imageTwoFx : 500.0, 501, 31.5, 23.5, 64, 48};
		sc.depthScale = 0.1;
		scene.cameras[im] = sc;
		scene.gt[im] = {};
		EXPECT_TRUE(writeDepthPng(ds->depthPath(7, im), testFrame(64, 48, static_cast<uint32_t>(im))).ok());
	}
	EXPECT_TRUE(ds->saveScene(scene).ok());
	return root;
}

TEST(RecordCli, FromBopHonoursSceneCameraAndRefusesChangingIntrinsics)
{
	const fs::path dir = freshTempDir("record_bop_scene");
	const fs::path root = makeBopScene(dir / "ds", 500);
	const fs::path out = dir / "scene.rec";
	CommandResult r = runIhf("record --from-bop " + root.string() + " --scene 7 --fps 20 --out " + out.string());
	ASSERT_EQ(r.exitCode, 0) << r.output;

	auto reader = RecordingReader::open(out);
	ASSERT_TRUE(reader.ok());
	EXPECT_EQ(reader->header().depthScale, 0.1); // scene_camera, not camera.json
	EXPECT_EQ(reader->header().intrinsics.fx, 500.0);
	ASSERT_EQ(reader->frameCount(), 3u);
	const uint64_t ids[] = {4, 5, 9};
	DepthImage16 frame(64, 48);
	for (size_t i = 0; i < 3; ++i) {
		recording::FrameRecord rec;
		ASSERT_EQ(*reader->read(i, rec, frame.view()), FrameCheck::kOk);
		EXPECT_EQ(rec.index, ids[i]);
		EXPECT_EQ(rec.hostTimestampNs, static_cast<int64_t>(i) * 50'000'000); // 20 fps
		EXPECT_EQ(depthDifference(frame.view(), testFrame(64, 48, static_cast<uint32_t>(ids[i]))), "");
	}

	const fs::path changing = makeBopScene(dir / "ds2", 510);
	r = runIhf("record --from-bop " + changing.string() + " --out " + (dir / "bad.rec").string());
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("scene_camera.json: image 5 has a different cam_K"), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(dir / "bad.rec"));
}

TEST(RecordCli, FromSourceCopiesFramesAndInfoFindsCorruption)
{
	const fs::path dir = freshTempDir("record_source");
	const fs::path in = dir / "in.rec";
	const TestStream s = testStream();
	writeStream(in, s, false);

	const fs::path out = dir / "out.rec";
	CommandResult r = runIhf("record --source recording:" + in.string() + " --frames 3 --compress --out " +
				 out.string());
	ASSERT_EQ(r.exitCode, 0) << r.output;
	auto reader = RecordingReader::open(out);
	ASSERT_TRUE(reader.ok());
	EXPECT_EQ(reader->header().sensorId, testHeader().sensorId);
	ASSERT_EQ(reader->frameCount(), 3u);
	DepthImage16 frame(64, 48);
	for (size_t i = 0; i < 3; ++i) {
		recording::FrameRecord rec;
		ASSERT_EQ(*reader->read(i, rec, frame.view()), FrameCheck::kOk);
		EXPECT_EQ(rec.index, s.indices[i]);
		EXPECT_EQ(rec.deviceTimestampNs, s.deviceNs[i]);
		EXPECT_EQ(rec.encoding, recording::Encoding::kZlib);
		EXPECT_EQ(depthDifference(frame.view(), s.frames[i]), "");
	}

	// A damaged frame: info names it and fails; a copy skips it.
	std::vector<uint8_t> bytes = readBytes(in);
	auto inReader = RecordingReader::open(in);
	ASSERT_TRUE(inReader.ok());
	bytes[inReader->entry(3).offset + 40 + 7] ^= 0x80;
	writeBytes(in, bytes);
	r = runIhf("record info " + in.string());
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("corrupt       frame 14 (position 3): CRC32 mismatch"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("(1 missing in between)"), std::string::npos) << r.output;
	r = runIhf("record --source recording:" + in.string() + " --out " + out.string());
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("4 frames"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("corrupt skipped 1"), std::string::npos) << r.output;
}

TEST(RecordCli, UsageAndRuntimeErrors)
{
	const fs::path dir = freshTempDir("record_usage");
	EXPECT_EQ(runIhf("record --help").exitCode, 0);
	EXPECT_EQ(runIhf("record info --help").exitCode, 0);
	EXPECT_EQ(runIhf("record --out " + (dir / "x.rec").string()).exitCode, 2);
	EXPECT_EQ(runIhf("record --from-bop " + lmoDir().string()).exitCode, 2);
	CommandResult r = runIhf("record --source bogus:thing --out " + (dir / "x.rec").string());
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("unknown scheme 'bogus'"), std::string::npos) << r.output;
	r = runIhf("record info " + (dir / "absent.rec").string());
	EXPECT_EQ(r.exitCode, 1);
	EXPECT_NE(r.output.find("absent.rec"), std::string::npos) << r.output;
	writeBytes(dir / "junk.rec", {'n', 'o', 't', ' ', 'a', ' ', 'r', 'e', 'c', '!'});
	r = runIhf("record info " + (dir / "junk.rec").string());
	EXPECT_EQ(r.exitCode, 1);
	EXPECT_NE(r.output.find("'magic'"), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(dir / "x.rec"));
}

} // namespace
} // namespace ihf::test
