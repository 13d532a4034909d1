// SPDX-License-Identifier: MIT
// `ihf eval --run-poses` end to end: pose lines written for the frames of a
// real `ihf record --from-bop` recording, each with the truth of the image
// its depth shows, come out right with no error (so eval maps frames back to
// images as record made them); bad lines exit 1 naming the line; frames and
// objects without ground truth are reported; usage errors exit 2.

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "drivers/recording_reader.h"
#include "tests/common/test_paths.h"
#include "tests/eval/run_pose_dataset.h"

namespace ihf::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A pose line as `ihf run` writes it (the fields eval reads, and some it ignores).
std::string poseLine(uint64_t frame, int objId, const Pose &pose)
{
	json j;
	j["frame"] = frame;
	j["obj_id"] = objId;
	std::vector<double> r;
	for (int i = 0; i < 9; ++i)
		r.push_back(pose.R(i / 3, i % 3));
	j["R"] = r;
	j["t"] = {pose.t.x(), pose.t.y(), pose.t.z()};
	j["confidence"] = 0.9;
	j["mode"] = "detect";
	return j.dump() + "\n";
}

std::string evalArgs(const fs::path &dataset, const fs::path &poses)
{
	return "eval --dataset " + dataset.string() + " --run-poses " + poses.string();
}

void expectIn(const std::string &output, const std::string &needle)
{
	EXPECT_NE(output.find(needle), std::string::npos) << "no \"" << needle << "\" in:\n" << output;
}

TEST(EvalRunPosesCli, PosesOfTheRecordedImagesAreRight)
{
	const fs::path dir = freshTempDir("eval_run_poses");
	makeRunPoseDataset(dir / "ds");
	CommandResult r = runIhf("record --from-bop " + (dir / "ds").string() + " --out " + (dir / "ds.rec").string());
	ASSERT_EQ(r.exitCode, 0) << r.output;

	// Each frame gets the truth of the image its depth (1000 + image id) shows.
	auto reader = RecordingReader::open(dir / "ds.rec");
	ASSERT_TRUE(reader.ok()) << reader.error().message;
	ASSERT_EQ(reader->frameCount(), 3u);
	std::string lines;
	DepthImage16 depth(64, 48);
	for (size_t i = 0; i < reader->frameCount(); ++i) {
		recording::FrameRecord rec;
		ASSERT_EQ(*reader->read(i, rec, depth.view()), FrameCheck::kOk);
		const int image = depth.at(0, 0) - 1000;
		lines += poseLine(rec.index, image == 9 ? 2 : 1, truthPose(image));
		if (image == 4) { // and once turned 10 deg about its centre
			Pose turned = truthPose(4);
			turned.R = turned.R * Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
			lines += poseLine(rec.index, 1, turned);
		}
	}
	lines += R"({"frame":5,"obj_id":1,"mode":"track","track_id":1,"error":"deferred"})"
		 "\n";
	std::ofstream(dir / "poses.jsonl") << lines;

	r = runIhf(evalArgs(dir / "ds", dir / "poses.jsonl"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	expectIn(r.output, "scene 7");
	expectIn(r.output, "4 of 4 poses right (ADD/ADI <= 0.1 d), 1 line without a pose; rotation error median "
			   "0.00 deg, max 10.00; translation median 0.00 mm, max 0.00\n");
	expectIn(r.output, "no pose: deferred");
}

TEST(EvalRunPosesCli, BadLinesExitOneNamingTheLine)
{
	const fs::path dir = freshTempDir("eval_run_poses_bad");
	makeRunPoseDataset(dir / "ds");
	const fs::path poses = dir / "poses.jsonl";

	std::ofstream(poses) << poseLine(4, 1, truthPose(4)) << R"({"frame":5,"obj_id":1,"R":[1,0,0],"t":[0,0,0]})"
			     << "\n";
	CommandResult r = runIhf(evalArgs(dir / "ds", poses));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	expectIn(r.output, poses.string() + " line 2: \"R\" is not 9 numbers");

	std::ofstream(poses) << "{\"frame\": 4,\n";
	r = runIhf(evalArgs(dir / "ds", poses));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	expectIn(r.output, poses.string() + " line 1: not JSON");

	r = runIhf(evalArgs(dir / "ds", dir / "absent.jsonl"));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	expectIn(r.output, "absent.jsonl");

	// Reported, not fatal: a frame beyond the scene's images, an object
	// without ground truth in its image.
	std::ofstream(poses) << poseLine(12, 1, truthPose(4)) << poseLine(4, 2, truthPose(4))
			     << poseLine(5, 1, truthPose(5));
	r = runIhf(evalArgs(dir / "ds", poses));
	EXPECT_EQ(r.exitCode, 0) << r.output;
	expectIn(r.output, "no truth: " + poses.string() + " line 1: frame 12 was not recorded from scene 7");
	expectIn(r.output, "no truth: " + poses.string() + " line 2: object 2 has no ground truth in image 4");
	expectIn(r.output, "1 of 1 poses right (ADD <= 0.1 d), 2 poses without ground truth;");
}

TEST(EvalRunPosesCli, SceneAndUsage)
{
	const fs::path dir = freshTempDir("eval_run_poses_usage");
	makeRunPoseDataset(dir / "ds", true);
	const fs::path poses = dir / "poses.jsonl";
	std::ofstream(poses) << poseLine(4, 1, truthPose(4));

	CommandResult r = runIhf(evalArgs(dir / "ds", poses));
	EXPECT_EQ(r.exitCode, 2) << r.output;
	expectIn(r.output, "choose one with --scene");
	r = runIhf(evalArgs(dir / "ds", poses) + " --scene 7");
	EXPECT_EQ(r.exitCode, 0) << r.output;
	expectIn(r.output, "1 of 1 poses right");

	const std::string ds = " --dataset " + (dir / "ds").string();
	EXPECT_EQ(runIhf("eval" + ds).exitCode, 2);
	EXPECT_EQ(runIhf("eval" + ds + " --results x.csv --run-poses " + poses.string()).exitCode, 2);
	EXPECT_EQ(runIhf("eval" + ds + " --run-poses " + poses.string() + " --json x.json").exitCode, 2);
	EXPECT_EQ(runIhf("eval" + ds + " --results x.csv --scene 7").exitCode, 2);
	EXPECT_EQ(runIhf("eval" + ds + " --run-poses " + poses.string() + " --scene -1").exitCode, 2);
	r = runIhf("eval --help");
	EXPECT_EQ(r.exitCode, 0);
	expectIn(r.output, "--run-poses");
}

} // namespace
} // namespace ihf::test
