// SPDX-License-Identifier: MIT
// How close a pose of `ihf run` came to the truth: comparePose() on one
// object, checkRunPoses() on a small dataset (frames to images, the nearest
// instance, no pose, no truth) and the table's summary line.

#include <cmath>

#include <gtest/gtest.h>

#include "core/eval/eval_dataset.h"
#include "core/eval/eval_report_text.h"
#include "core/eval/run_pose_check.h"
#include "tests/common/test_paths.h"
#include "tests/eval/run_pose_dataset.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;
using test::truthPose;

struct Box {
	ObjectPoseError error{test::boxMesh().vertices, PoseMetric::kAdd};
	EvalObject object{test::kBoxDiameter, &error};
};

RunPoseCheck compare(const Pose &estimate, const std::vector<Pose> &truths, const EvalObject &object)
{
	RunPoseCheck check;
	comparePose(estimate, truths, object, kRecallZ, check);
	return check;
}

TEST(RunPoseCheck, ThePoseOfTheTruthIsRightWithNoError)
{
	const Box box;
	const RunPoseCheck c = compare(truthPose(4), {truthPose(4)}, box.object);
	EXPECT_EQ(c.verdict, RunPoseVerdict::kRight);
	EXPECT_EQ(c.metric, PoseMetric::kAdd);
	EXPECT_NEAR(c.rotationDeg, 0, 1e-5); // acos near 1: a rounding of R shows
	EXPECT_EQ(c.translationMm, 0);
	EXPECT_EQ(c.errorMm, 0);
	EXPECT_EQ(c.errorShare, 0);
}

TEST(RunPoseCheck, TurnedTenDegreesAboutItsCentre)
{
	const Box box;
	const Pose truth = truthPose(4);
	Pose turned = truth;
	// The box is centred on its origin: a turn in its own frame moves no centre.
	turned.R = truth.R * Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	const RunPoseCheck c = compare(turned, {truth}, box.object);
	EXPECT_NEAR(c.rotationDeg, 10.0, 1e-9);
	EXPECT_NEAR(c.translationMm, 0, 1e-12);
	// Every corner is sqrt(30^2 + 20^2) from the z axis and moves 2 sin(5 deg) of that.
	const double add = 2 * std::sin(5 * M_PI / 180) * std::sqrt(30.0 * 30 + 20 * 20);
	EXPECT_NEAR(c.errorMm, add, 1e-9);
	EXPECT_NEAR(c.errorShare, add / test::kBoxDiameter, 1e-12);
	EXPECT_EQ(c.verdict, RunPoseVerdict::kRight); // 6.3 mm, under 0.1 d = 7.5 mm

	turned.R = truth.R * Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	const RunPoseCheck wrong = compare(turned, {truth}, box.object);
	EXPECT_NEAR(wrong.rotationDeg, 20.0, 1e-9);
	EXPECT_EQ(wrong.verdict, RunPoseVerdict::kWrong);
}

TEST(RunPoseCheck, ComparesWithTheNearestInstance)
{
	const Box box;
	Pose far = truthPose(5), near = truthPose(5);
	far.t.z() += 500;
	near.t.x() += 3;
	const RunPoseCheck c = compare(truthPose(5), {far, near}, box.object);
	EXPECT_NEAR(c.translationMm, 3, 1e-9);
	EXPECT_NEAR(c.errorMm, 3, 1e-9);
	EXPECT_EQ(c.verdict, RunPoseVerdict::kRight);
}

fs::path datasetDir(const std::string &name, bool secondScene = false)
{
	const fs::path root = test::freshTempDir(name) / "ds";
	test::makeRunPoseDataset(root, secondScene);
	return root;
}

RunPoseLine poseLine(size_t line, uint64_t frame, int objId, const Pose &pose)
{
	return {.line = line, .frame = frame, .objId = objId, .pose = pose, .error = {}};
}

TEST(RunPoseCheck, FramesMapToTheImagesOfTheScene)
{
	const fs::path root = datasetDir("run_pose_check_scene");
	auto ds = BopDataset::open(root);
	ASSERT_TRUE(ds.ok()) << ds.error().message;

	Pose halfTurned = truthPose(9);
	halfTurned.R = halfTurned.R * Eigen::Vector3d(-1, -1, 1).asDiagonal();
	const RunPoseLine deferred{
		.line = 4, .frame = 5, .objId = 1, .pose = std::nullopt, .error = "deferred: waiting for its detection"};
	const std::vector<RunPoseLine> lines = {
		poseLine(1, 4, 1, truthPose(4)),
		poseLine(2, 5, 1, truthPose(4)), // the pose of image 4 in image 5: wrong
		poseLine(3, 9, 2, halfTurned),   // the object's own symmetry: right by ADI
		deferred,
		poseLine(5, 6, 1, truthPose(4)), // no image 6
		poseLine(6, 4, 2, truthPose(4)), // no object 2 in image 4
	};
	RunPoseRequest request;
	request.posesFile = "run.jsonl";
	auto report = checkRunPoses(*ds, lines, request);
	ASSERT_TRUE(report.ok()) << report.error().message;
	EXPECT_EQ(report->sceneId, test::kRunPoseScene);
	const std::vector<RunPoseCheck> &c = report->checks;
	ASSERT_EQ(c.size(), lines.size());

	EXPECT_EQ(c[0].verdict, RunPoseVerdict::kRight);
	EXPECT_EQ(c[0].sceneId, 7);
	EXPECT_EQ(c[0].imageId, 4);
	EXPECT_NEAR(c[0].rotationDeg, 0, 1e-5);
	EXPECT_NEAR(c[0].translationMm, 0, 1e-9);

	EXPECT_EQ(c[1].verdict, RunPoseVerdict::kWrong);
	EXPECT_EQ(c[1].imageId, 5);
	EXPECT_NEAR(c[1].rotationDeg, 0.1 * 180 / M_PI, 1e-6); // truthPose turns 0.1 rad per image id
	EXPECT_NEAR(c[1].translationMm, (truthPose(5).t - truthPose(4).t).norm(), 1e-6);

	EXPECT_EQ(c[2].verdict, RunPoseVerdict::kRight);
	EXPECT_EQ(c[2].metric, PoseMetric::kAdi);
	EXPECT_NEAR(c[2].rotationDeg, 180, 1e-5);
	EXPECT_NEAR(c[2].errorMm, 0, 1e-6);

	EXPECT_EQ(c[3].verdict, RunPoseVerdict::kNoPose);
	EXPECT_EQ(c[3].imageId, 5);
	EXPECT_EQ(c[3].note, "deferred: waiting for its detection");

	EXPECT_EQ(c[4].verdict, RunPoseVerdict::kNoTruth);
	EXPECT_EQ(c[4].imageId, -1);
	EXPECT_EQ(c[4].note, "run.jsonl line 5: frame 6 was not recorded from scene 7 (3 images, ids 4..9)");

	EXPECT_EQ(c[5].verdict, RunPoseVerdict::kNoTruth);
	EXPECT_EQ(c[5].imageId, 4);
	EXPECT_EQ(c[5].note, "run.jsonl line 6: object 2 has no ground truth in image 4 of scene 7");

	const std::string table = formatRunPoseTable(*report);
	EXPECT_NE(table.find("2 of 3 poses right (ADD/ADI <= 0.1 d), 1 line without a pose, "
			     "2 poses without ground truth; rotation error median "),
		  std::string::npos)
		<< table;
	EXPECT_NE(table.find("no truth: run.jsonl line 5: frame 6"), std::string::npos) << table;
	EXPECT_NE(table.find("no pose: deferred"), std::string::npos) << table;
	EXPECT_NE(table.find(", max 180.00;"), std::string::npos) << table;
}

TEST(RunPoseCheck, SeveralScenesNeedOneChosen)
{
	const fs::path root = datasetDir("run_pose_check_scenes", true);
	auto ds = BopDataset::open(root);
	ASSERT_TRUE(ds.ok()) << ds.error().message;
	const std::vector<RunPoseLine> lines = {poseLine(1, 4, 1, truthPose(4))};

	auto unchosen = checkRunPoses(*ds, lines, RunPoseRequest{});
	ASSERT_FALSE(unchosen.ok());
	EXPECT_EQ(unchosen.error().code, Errc::kInvalidArgument);
	EXPECT_NE(unchosen.error().message.find("2 scenes (7, 8); choose one with --scene"), std::string::npos)
		<< unchosen.error().message;

	RunPoseRequest request;
	request.sceneId = 7;
	auto chosen = checkRunPoses(*ds, lines, request);
	ASSERT_TRUE(chosen.ok()) << chosen.error().message;
	EXPECT_EQ(chosen->checks.at(0).verdict, RunPoseVerdict::kRight);

	request.sceneId = 8; // frame 4 is no image of scene 8
	auto other = checkRunPoses(*ds, lines, request);
	ASSERT_TRUE(other.ok()) << other.error().message;
	EXPECT_EQ(other->checks.at(0).verdict, RunPoseVerdict::kNoTruth);
}

TEST(RunPoseCheck, AnEmptyRunSaysSo)
{
	const std::string table = formatRunPoseTable(RunPoseReport{});
	EXPECT_EQ(table.substr(table.find('\n') + 1), "0 of 0 poses right (ADD <= 0.1 d)\n");
}

} // namespace
} // namespace ihf
