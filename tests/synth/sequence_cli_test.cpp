// SPDX-License-Identifier: MIT
// `ihf synth --sequence` end to end: a small set (two short sequences, a
// half-size camera) in BOP layout with its recordings, the recordings'
// frames equal to the PNGs at 30 fps and their box lines equal to
// boxes.json, camera motion within the limits as the written ground truth
// shows it, byte-identical files for a seed, and bad requests refused
// naming the option, with nothing left behind.

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <set>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "drivers/recording_reader.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

std::vector<uint16_t> pixels(const DepthImage16 &image)
{
	const auto p = image.pixels();
	return {p.begin(), p.end()};
}

const auto q = test::quoted; // a path in single quotes, for the shell

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

class SequenceCli : public ::testing::Test
{
protected:
	static std::string command(uint64_t seed, const fs::path &out)
	{
		return "synth --sequence --models " + q(test::lmoDir() / "models") +
		       " --objects 1,9,11 --per-frame 3:3 --sequences 2 --frames 12 --camera " +
		       q(*dir_ / "camera.json") + " --seed " + std::to_string(seed) + " --quiet --out " + q(out);
	}
	static void SetUpTestSuite()
	{
		dir_ = new fs::path(test::freshTempDir("synth_seq_cli_" + std::to_string(::getpid())));
		std::ofstream(*dir_ / "camera.json")
			<< R"({"width": 320, "height": 240, "fx": 286.2057, "fy": 286.785215, "cx": 162.63055, "cy": 121.024495, "depth_scale": 1.0})";
		const auto r = test::runIhf(command(3, *dir_ / "a"));
		ASSERT_EQ(r.exitCode, 0) << r.output;
	}
	static void TearDownTestSuite()
	{
		fs::remove_all(*dir_);
		delete dir_;
	}
	static fs::path *dir_;
};

fs::path *SequenceCli::dir_ = nullptr;

TEST_F(SequenceCli, WritesBopScenesWithEveryVisibleTarget)
{
	const fs::path a = *dir_ / "a";
	for (const char *f : {"camera.json", "boxes.json", "synth_config.json", "sequences.json",
			      "models/models_info.json", "models/obj_000009.ply", "test/000001/scene_gt.json",
			      "test/000002/scene_gt_info.json", "test/000002/depth/000011.png",
			      "recordings/000001.rec", "recordings/000002.boxes.jsonl"})
		EXPECT_TRUE(fs::exists(a / f)) << f;
	auto ds = BopDataset::open(a);
	ASSERT_TRUE(ds) << ds.error().message;
	EXPECT_EQ(ds->sceneIds(), (std::vector<int>{1, 2}));
	EXPECT_EQ(ds->camera().intrinsics.width, 320);
	auto boxes = readDetections(a / "boxes.json");
	ASSERT_TRUE(boxes) << boxes.error().message;
	const nlohmann::json described = nlohmann::json::parse(readAll(a / "sequences.json"));
	ASSERT_EQ(described.size(), 2u);
	for (int sceneId : {1, 2}) {
		auto scene = ds->loadScene(sceneId);
		ASSERT_TRUE(scene) << scene.error().message;
		ASSERT_EQ(scene->cameras.size(), 12u);
		int im = 0;
		for (const auto &[id, cam] : scene->cameras)
			EXPECT_EQ(id, im++); // image id = frame index
		const auto &d = described[static_cast<size_t>(sceneId - 1)];
		EXPECT_EQ(d["targets"].size(), 3u);
		EXPECT_GE(d["events"].size(), 1u);
		int listed = 0;
		for (const auto &[id, gts] : scene->gt) {
			std::set<int> ids;
			for (size_t k = 0; k < gts.size(); ++k) {
				EXPECT_TRUE(ids.insert(gts[k].objId).second);
				const GtInfo &info = scene->gtInfo.at(id).at(k);
				EXPECT_GT(info.pxCountVisib, 0); // only visible targets are listed
				++listed;
				// A box unless too little is visible (0.03 misses aside).
				int n = 0;
				for (const Detection &b : *boxes)
					n += b.sceneId == sceneId && b.imageId == id && b.categoryId == gts[k].objId;
				EXPECT_LE(n, 1);
				if (info.visibFract < 0.1) {
					EXPECT_EQ(n, 0);
				}
			}
		}
		EXPECT_GT(listed, 12);
	}
}

TEST_F(SequenceCli, RecordingsEqualThePngsAndBoxLinesEqualBoxesJson)
{
	const fs::path a = *dir_ / "a";
	auto ds = BopDataset::open(a);
	ASSERT_TRUE(ds);
	auto boxes = readDetections(a / "boxes.json");
	ASSERT_TRUE(boxes);
	for (int sceneId : {1, 2}) {
		char name[16];
		std::snprintf(name, sizeof(name), "%06d", sceneId);
		auto reader = RecordingReader::open(a / "recordings" / (std::string(name) + ".rec"));
		ASSERT_TRUE(reader) << reader.error().message;
		ASSERT_EQ(reader->frameCount(), 12u);
		EXPECT_EQ(reader->header().intrinsics.width, 320);
		EXPECT_EQ(reader->header().intrinsics.fx, 286.2057);
		DepthImage16 frame(320, 240);
		for (size_t i = 0; i < 12; ++i) {
			recording::FrameRecord rec;
			ASSERT_EQ(*reader->read(i, rec, frame.view()), FrameCheck::kOk);
			EXPECT_EQ(rec.index, i);
			EXPECT_EQ(rec.hostTimestampNs, std::llround(i * 1e9 / 30.0)); // 30 fps
			auto png = readDepthPng(ds->depthPath(sceneId, static_cast<int>(i)));
			ASSERT_TRUE(png);
			EXPECT_EQ(pixels(frame), pixels(*png)) << "frame " << i;
		}
		std::ifstream lines(a / "recordings" / (std::string(name) + ".boxes.jsonl"));
		std::string line;
		int f = 0;
		while (std::getline(lines, line)) {
			const nlohmann::json j = nlohmann::json::parse(line);
			EXPECT_EQ(j["frame"].get<int>(), f);
			std::vector<const Detection *> expected;
			for (const Detection &b : *boxes)
				if (b.sceneId == sceneId && b.imageId == f)
					expected.push_back(&b);
			ASSERT_EQ(j["boxes"].size(), expected.size()) << "frame " << f;
			for (size_t k = 0; k < expected.size(); ++k) {
				EXPECT_EQ(j["boxes"][k]["obj_id"].get<int>(), expected[k]->categoryId);
				for (int c = 0; c < 4; ++c)
					EXPECT_EQ(j["boxes"][k]["bbox"][c].get<double>(), expected[k]->bbox[c]);
			}
			++f;
		}
		EXPECT_EQ(f, 12);
	}
}

TEST_F(SequenceCli, GroundTruthCameraMovesWithinTheLimits)
{
	// Camera motion between frames from an object resting in both: its
	// model frame is fixed in the world, so the camera's centre and
	// rotation in it move as the camera does.
	const fs::path a = *dir_ / "a";
	auto ds = BopDataset::open(a);
	ASSERT_TRUE(ds);
	const nlohmann::json described = nlohmann::json::parse(readAll(a / "sequences.json"));
	int pairs = 0;
	for (int sceneId : {1, 2}) {
		auto scene = ds->loadScene(sceneId);
		ASSERT_TRUE(scene);
		std::set<int> carried; // objects with an event
		for (const auto &e : described[static_cast<size_t>(sceneId - 1)]["events"])
			carried.insert(e["obj_id"].get<int>());
		for (int f = 0; f + 1 < 12; ++f) {
			for (const GtInstance &g0 : scene->gt.at(f)) {
				if (carried.count(g0.objId))
					continue;
				for (const GtInstance &g1 : scene->gt.at(f + 1)) {
					if (g1.objId != g0.objId)
						continue;
					const Eigen::Vector3d c0 = -g0.pose.R.transpose() * g0.pose.t;
					const Eigen::Vector3d c1 = -g1.pose.R.transpose() * g1.pose.t;
					// JSON keeps the poses to ~1e-6 relative: allow 0.1 mm.
					EXPECT_LE((c1 - c0).norm() * 30.0, 500.0 + 3.0) << sceneId << "/" << f;
					EXPECT_LE(rotationAngle(g0.pose.R, g1.pose.R) * 30.0 * 180 / std::numbers::pi, 90.0 + 0.1);
					++pairs;
				}
			}
		}
	}
	EXPECT_GT(pairs, 10);
}

TEST_F(SequenceCli, SameSeedIdenticalFilesOtherSeedDifferent)
{
	const fs::path a = *dir_ / "a", b = *dir_ / "b", c = *dir_ / "c";
	auto r = test::runIhf(command(3, b));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto files = filesUnder(a);
	ASSERT_EQ(files, filesUnder(b));
	for (const auto &f : files)
		EXPECT_EQ(readAll(a / f), readAll(b / f)) << f;
	r = test::runIhf(command(4, c));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(readAll(a / "test/000001/depth/000000.png"), readAll(c / "test/000001/depth/000000.png"));
	EXPECT_NE(readAll(a / "boxes.json"), readAll(c / "boxes.json"));
	EXPECT_NE(readAll(a / "recordings/000002.rec"), readAll(c / "recordings/000002.rec"));
}

struct BadCase {
	std::string args;
	std::string mentions;
};

TEST(SequenceCliErrors, BadRequestsNameTheOptionAndLeaveNothing)
{
	const fs::path dir = test::freshTempDir("synth_seq_bad_" + std::to_string(::getpid()));
	const fs::path out = dir / "out";
	const std::string m = "--models " + q(test::lmoDir() / "models");
	const std::vector<BadCase> cases = {
		{"--sequence " + m + " --objects 1,9,11 --images 3", "--images"},
		{"--sequence " + m + " --objects 1,9,11 --occlusion 0:0.2", "--occlusion"},
		{"--sequence " + m + " --objects 1,9,11 --per-frame 3:4", "--per-frame"},
		{"--sequence " + m + " --objects 1,9,11 --per-frame 2.5:3", "--per-frame"},
		{"--sequence " + m + " --objects 1,9,11 --motion jog", "--motion 'jog'"},
		{"--sequence " + m + " --objects 1,9,11 --frames 0", "--frames"},
		{"--sequence " + m + " --objects 1,9,11 --sequences 0", "--sequences"},
		{"--sequence " + m + " --objects 1,9,11 --miss 1.5", "--miss"},
		{"--sequence " + m + " --objects 1,9,11 --max-speed 0", "--max-speed"},
		{"--sequence " + m + " --objects 1,9,11 --distance 300:900", "--distance"},
		{m + " --objects 1 --frames 10", "--frames"},
	};
	for (const auto &c : cases) {
		SCOPED_TRACE(c.args);
		const auto r = test::runIhf("synth " + c.args + " --quiet --out " + q(out));
		EXPECT_EQ(r.exitCode, 2) << r.output;
		EXPECT_NE(r.output.find(c.mentions), std::string::npos) << r.output;
		EXPECT_FALSE(fs::exists(out));
		EXPECT_TRUE(fs::is_empty(dir)) << "something was left in " << dir;
	}
	const auto r = test::runIhf("synth --sequence --models " + q(dir / "nowhere") +
				    " --objects 1,9,11 --quiet --out " + q(out));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("nowhere"), std::string::npos) << r.output;
	EXPECT_TRUE(fs::is_empty(dir));
	fs::remove_all(dir);
}

} // namespace
} // namespace ihf
