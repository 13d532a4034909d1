// SPDX-License-Identifier: MIT
// `ihf synth` end to end: a small set written, byte-identical for a seed,
// different for another, readable by the BOP reader, with boxes that cover
// the objects, and bad requests refused with nothing left behind.

#include <fstream>
#include <iterator>
#include <set>

#include <unistd.h>

#include <gtest/gtest.h>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "core/geometry/ply_loader.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

std::string models() { return std::string("'").append((test::lmoDir() / "models").string()).append("'"); }

std::string readAll(const fs::path &p)
{
	std::ifstream in(p, std::ios::binary);
	return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::set<fs::path> filesUnder(const fs::path &root)
{
	std::set<fs::path> files;
	for (const auto &e : fs::recursive_directory_iterator(root))
		if (e.is_regular_file())
			files.insert(fs::relative(e.path(), root));
	return files;
}

class SynthCli : public ::testing::Test
{
protected:
	// One small set shared by the tests (two objects, three images each).
	static void SetUpTestSuite()
	{
		// ctest runs every case in its own process, maybe in parallel:
		// one folder per process.
		dir_ = new fs::path(test::freshTempDir("synth_cli_" + std::to_string(::getpid())));
		const auto r = test::runIhf("synth --models " + models() +
					    " --objects 1,5 --images 3 --seed 7 --occlusion 0.1:0.5 --out '" +
					    (*dir_ / "a").string() + "'");
		ASSERT_EQ(r.exitCode, 0) << r.output;
	}
	static void TearDownTestSuite()
	{
		fs::remove_all(*dir_);
		delete dir_;
	}
	static fs::path *dir_;
};

fs::path *SynthCli::dir_ = nullptr;

TEST_F(SynthCli, WritesTheBopLayout)
{
	const fs::path a = *dir_ / "a";
	for (const char *f : {"camera.json", "boxes.json", "synth_config.json",
			      "models/models_info.json", "models/obj_000001.ply", "models/obj_000005.ply",
			      "test/000001/scene_gt.json", "test/000001/scene_gt_info.json",
			      "test/000001/scene_camera.json", "test/000005/depth/000002.png"})
		EXPECT_TRUE(fs::exists(a / f)) << f;
	// The meshes are copies of the source models.
	EXPECT_EQ(readAll(a / "models/obj_000005.ply"),
		  readAll(test::lmoDir() / "models/obj_000005.ply"));
	// No staging folder left beside it.
	for (const auto &e : fs::directory_iterator(*dir_))
		EXPECT_EQ(e.path().filename().string().find(".a.synth"), std::string::npos);
}

TEST_F(SynthCli, ReadableByTheBopReaderWithConsistentGroundTruth)
{
	auto ds = BopDataset::open(*dir_ / "a");
	ASSERT_TRUE(ds) << ds.error().message;
	EXPECT_EQ(ds->sceneIds(), (std::vector<int>{1, 5}));
	EXPECT_NEAR(ds->camera().intrinsics.fx, 572.4114, 1e-6);
	EXPECT_EQ(ds->camera().intrinsics.width, 640);
	ASSERT_EQ(ds->modelsInfo().size(), 2u);
	auto boxes = readDetections(*dir_ / "a" / "boxes.json");
	ASSERT_TRUE(boxes) << boxes.error().message;
	EXPECT_EQ(boxes->size(), 6u);
	for (int scene : {1, 5}) {
		auto s = ds->loadScene(scene);
		ASSERT_TRUE(s) << s.error().message;
		ASSERT_EQ(s->gt.size(), 3u);
		for (const auto &[im, gts] : s->gt) {
			ASSERT_EQ(gts.size(), 1u);
			EXPECT_EQ(gts[0].objId, scene);
			const double d = gts[0].pose.t.norm();
			EXPECT_GE(d, 700 - 1e-3);
			EXPECT_LE(d, 800 + 1e-3);
			const GtInfo &info = s->gtInfo.at(im).at(0);
			EXPECT_GE(1 - info.visibFract, 0.1 - 1e-9);
			EXPECT_LE(1 - info.visibFract, 0.5 + 1e-9);
			auto depth = ds->loadDepthMm(scene, im, s->cameras.at(im).depthScale);
			ASSERT_TRUE(depth) << depth.error().message;
			EXPECT_EQ(depth->width(), 640);
			// The depth under the visible box has data near the pose's range.
			int near = 0, valid = 0;
			for (int y = info.bboxVisib[1]; y <= info.bboxVisib[1] + info.bboxVisib[3]; ++y)
				for (int x = info.bboxVisib[0]; x <= info.bboxVisib[0] + info.bboxVisib[2]; ++x) {
					const float z = depth->at(x, y);
					valid += z > 0;
					near += z > 0 && std::abs(z - gts[0].pose.t.z()) < 200;
				}
			EXPECT_GT(near, valid / 3);
			// The coarse box: clipped, and covering most of the object.
			const Detection *det = nullptr;
			for (const auto &b : *boxes)
				if (b.sceneId == scene && b.imageId == im)
					det = &b;
			ASSERT_NE(det, nullptr);
			EXPECT_EQ(det->categoryId, scene);
			EXPECT_GE(det->bbox[0], 0);
			EXPECT_GE(det->bbox[1], 0);
			EXPECT_LE(det->bbox[0] + det->bbox[2], 640);
			EXPECT_LE(det->bbox[1] + det->bbox[3], 480);
			const auto &o = info.bboxObj;
			const double ox0 = std::max(o[0], 0), oy0 = std::max(o[1], 0);
			const double ox1 = std::min(o[0] + o[2], 640), oy1 = std::min(o[1] + o[3], 480);
			const double ix = std::min(ox1, det->bbox[0] + det->bbox[2]) - std::max(ox0, det->bbox[0]);
			const double iy = std::min(oy1, det->bbox[1] + det->bbox[3]) - std::max(oy0, det->bbox[1]);
			EXPECT_GE(std::max(ix, 0.0) * std::max(iy, 0.0), 0.8 * (ox1 - ox0) * (oy1 - oy0));
		}
	}
}

TEST_F(SynthCli, SameSeedIdenticalFilesOtherSeedDifferent)
{
	const fs::path a = *dir_ / "a", b = *dir_ / "b", c = *dir_ / "c";
	auto r = test::runIhf("synth --models " + models() +
			      " --objects 1,5 --images 3 --seed 7 --occlusion 0.1:0.5 --quiet --out '" +
			      b.string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto files = filesUnder(a);
	ASSERT_EQ(files, filesUnder(b));
	for (const auto &f : files)
		EXPECT_EQ(readAll(a / f), readAll(b / f)) << f;

	r = test::runIhf("synth --models " + models() +
			 " --objects 1,5 --images 3 --seed 8 --occlusion 0.1:0.5 --quiet --out '" +
			 c.string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(readAll(a / "test/000001/depth/000000.png"), readAll(c / "test/000001/depth/000000.png"));
	EXPECT_NE(readAll(a / "test/000005/scene_gt.json"), readAll(c / "test/000005/scene_gt.json"));
	EXPECT_NE(readAll(a / "boxes.json"), readAll(c / "boxes.json"));
}

TEST_F(SynthCli, TheTimeOfFlightSensorSeesTheSameScenesOtherwise)
{
	const fs::path a = *dir_ / "a", t = *dir_ / "tof";
	const auto r = test::runIhf("synth --models " + models() +
				    " --objects 1,5 --images 3 --seed 7 --occlusion 0.1:0.5 --sensor tof --quiet --out '" +
				    t.string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	// The sensor draws after the layout: the same ground truth, so one
	// boxes.json serves both sets; the depth is another sensor's.
	for (const char *f : {"test/000001/scene_gt.json", "test/000005/scene_gt.json", "camera.json"})
		EXPECT_EQ(readAll(a / f), readAll(t / f)) << f;
	EXPECT_NE(readAll(a / "test/000001/depth/000000.png"), readAll(t / "test/000001/depth/000000.png"));
	EXPECT_NE(readAll(t / "synth_config.json").find("\"sensor\": \"tof\""), std::string::npos)
		<< readAll(t / "synth_config.json");
	EXPECT_NE(readAll(a / "synth_config.json").find("\"sensor\": \"kinect-v1\""), std::string::npos);
}

struct BadCase {
	std::string args;
	int exitCode;
	std::string mentions;
};

TEST(SynthCliErrors, BadRequestsFailClearlyAndLeaveNothing)
{
	const fs::path dir = test::freshTempDir("synth_cli_bad_" + std::to_string(::getpid()));
	const fs::path out = dir / "out";
	const std::string m = models();
	const std::vector<BadCase> cases = {
		{"--models '" + (dir / "nowhere").string() + "' --objects 1 --images 1", 1, "nowhere"},
		{"--models " + m + " --objects 1,99 --images 1", 1, "99"},
		{"--models " + m + " --objects 1 --images 1 --distance 800:700", 2, "--distance"},
		{"--models " + m + " --objects 1 --images 1 --occlusion 0:1.5", 2, "--occlusion"},
		{"--models " + m + " --objects 1 --images 1 --occlusion 0.3", 2, "--occlusion"},
		{"--models " + m + " --objects 1 --images 1 --occlusion 0:0", 0, ""}, // fully visible
		{"--models " + m + " --objects 1,x --images 1", 2, "--objects"},
		{"--models " + m + " --objects 1 --images 0", 2, "--images"},
		{"--models " + m + " --objects 1 --images 1 --sensor sonar", 2, "--sensor 'sonar'"},
	};
	for (const auto &c : cases) {
		SCOPED_TRACE(c.args);
		fs::remove_all(out);
		const auto r = test::runIhf("synth " + c.args + " --quiet --out '" + out.string() + "'");
		if (c.exitCode == 0) {
			// The parser accepts it: a one-image run.
			EXPECT_EQ(r.exitCode, 0) << r.output;
			fs::remove_all(out);
			continue;
		}
		EXPECT_EQ(r.exitCode, c.exitCode) << r.output;
		EXPECT_NE(r.output.find(c.mentions), std::string::npos) << r.output;
		EXPECT_FALSE(fs::exists(out));
		EXPECT_TRUE(fs::is_empty(dir)) << "something was left in " << dir;
	}
	// An existing output folder is not touched without --overwrite.
	fs::create_directories(out);
	std::ofstream(out / "keep.txt") << "mine";
	const auto r = test::runIhf("synth --models " + m + " --objects 1 --images 1 --out '" + out.string() + "'");
	EXPECT_NE(r.exitCode, 0);
	EXPECT_EQ(readAll(out / "keep.txt"), "mine");
	fs::remove_all(dir);
}

// --make-object writes the mesh and its models_info.json entry beside the
// entries already there; --without-part the body alone; a synthetic set
// then takes the object as it takes the LM-O meshes.
TEST(SynthCliObjects, MakeObjectWritesTheMeshAndItsModelsInfoEntry)
{
	const fs::path dir = test::freshTempDir("synth_cli_objects_" + std::to_string(::getpid()));
	const fs::path models = dir / "models";
	auto r = test::runIhf("synth --make-object cup --id 31 --models '" + models.string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	r = test::runIhf("synth --make-object camera --id 32 --models '" + models.string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	auto info = readModelsInfo(models / "models_info.json");
	ASSERT_TRUE(info.ok()) << info.error().message;
	ASSERT_EQ(info->size(), 2u);
	EXPECT_NEAR(info->at(31).size.z(), 95.0, 1e-3);
	EXPECT_GT(info->at(31).diameter, 100.0);
	EXPECT_FALSE(info->at(32).symmetric()); // the lens tells the turns apart
	auto cup = loadPly(models / "obj_000031.ply");
	ASSERT_TRUE(cup.ok());
	EXPECT_TRUE(isClosedOutward(*cup));

	r = test::runIhf("synth --make-object cup --id 31 --without-part --models '" + (dir / "bodies").string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	auto body = loadPly(dir / "bodies" / "obj_000031.ply");
	ASSERT_TRUE(body.ok());
	EXPECT_LT(body->vertices.size(), cup->vertices.size());

	r = test::runIhf("synth --models '" + models.string() + "' --objects 31 --images 2 --seed 5 --quiet --out '" +
			 (dir / "syn").string() + "'");
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_TRUE(fs::exists(dir / "syn" / "boxes.json"));

	EXPECT_EQ(test::runIhf("synth --make-object kettle --id 40 --models '" + models.string() + "'").exitCode, 2);
	EXPECT_EQ(test::runIhf("synth --make-object cup --models '" + models.string() + "'").exitCode, 2);
	EXPECT_EQ(test::runIhf("synth --make-object cup --id 31 --images 3 --models '" + models.string() + "'").exitCode,
		  2);
	fs::remove_all(dir);
}

} // namespace
} // namespace ihf
