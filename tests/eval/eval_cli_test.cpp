// SPDX-License-Identifier: MIT
// `ihf eval` end to end on the shared LM-O frame: its own ground truth
// scores perfectly, a perturbed copy fails where it should, bad inputs exit 1
// naming the file, usage errors exit 2.

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/dataset/bop_io.h"
#include "core/eval/pr_plot.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kSceneGt = test::lmoDir() / "test" / "000002" / "scene_gt.json";
const std::vector<int> kObjects = {1, 5, 6, 8, 9, 10, 11, 12};

const auto q = test::quoted; // a path in single quotes, for the shell

// The frame's ground truth as results rows (score 1, 0.5 s per image).
std::vector<ResultRow> groundTruthRows()
{
	auto gt = readSceneGt(kSceneGt);
	EXPECT_TRUE(gt.ok()) << gt.error().message;
	std::vector<ResultRow> rows;
	for (const auto &[imId, instances] : *gt)
		for (const GtInstance &inst : instances) {
			ResultRow r;
			r.sceneId = 2;
			r.imId = imId;
			r.objId = inst.objId;
			r.score = 1.0;
			r.pose = inst.pose;
			r.time = 0.5;
			rows.push_back(r);
		}
	return rows;
}

json readJson(const fs::path &file)
{
	std::ifstream in(file);
	return json::parse(in);
}

std::string evalArgs(const fs::path &results)
{
	return "eval --dataset " + q(test::lmoDir()) + " --split test --results " + q(results);
}

const json &objectEntry(const json &doc, int objId)
{
	for (const json &o : doc["objects"])
		if (o["obj_id"] == objId)
			return o;
	static const json none;
	ADD_FAILURE() << "object " << objId << " missing from the report";
	return none;
}

TEST(EvalCli, GroundTruthScoresOneEverywhere)
{
	const fs::path dir = test::freshTempDir("eval_cli_gt");
	ASSERT_TRUE(writeResultsCsv(dir / "gt.csv", groundTruthRows()).ok());
	std::string args = evalArgs(dir / "gt.csv") + " --json " + q(dir / "report.json");
	if (prPlotSupported())
		args += " --plot " + q(dir / "pr.png");

	auto res = test::runIhf(args);
	ASSERT_EQ(res.exitCode, 0) << res.output;
	EXPECT_NE(res.output.find("mean"), std::string::npos) << res.output;

	const json doc = readJson(dir / "report.json");
	ASSERT_EQ(doc["objects"].size(), kObjects.size());
	for (int id : kObjects) {
		const json &o = objectEntry(doc, id);
		EXPECT_EQ(o["metric"], id == 10 || id == 11 ? "ADI" : "ADD") << "object " << id;
		EXPECT_EQ(o["num_gt"], 1);
		EXPECT_EQ(o["num_estimates"], 1);
		ASSERT_EQ(o["f1"].size(), 11u);
		for (const json &f : o["f1"])
			EXPECT_EQ(f.get<double>(), 1.0) << "object " << id;
		EXPECT_EQ(o["recall_0.1d"].get<double>(), 1.0);
		EXPECT_EQ(o["median_time"].get<double>(), 0.5);
		ASSERT_EQ(o["pr_curve_z0.10"].size(), 1u);
	}
	EXPECT_EQ(doc["mean"]["mean_f1"].get<double>(), 1.0);
	EXPECT_EQ(doc["mean"]["recall_0.1d"].get<double>(), 1.0);
	EXPECT_EQ(doc["mean"]["num_gt"], 8);

	if (prPlotSupported()) {
		std::ifstream png(dir / "pr.png", std::ios::binary);
		char sig[8] = {};
		png.read(sig, 8);
		EXPECT_EQ(std::string(sig + 1, 3), "PNG");
		EXPECT_GT(fs::file_size(dir / "pr.png"), 10000u);
	}
}

TEST(EvalCli, PerturbedResultsFailWhereExpected)
{
	const fs::path dir = test::freshTempDir("eval_cli_perturbed");
	auto info = readModelsInfo(test::lmoDir() / "models" / "models_info.json");
	ASSERT_TRUE(info.ok());

	std::vector<ResultRow> rows;
	for (ResultRow r : groundTruthRows()) {
		switch (r.objId) {
		case 1: // 0.115 diameters along camera x: ADD = that length
			r.pose.t.x() += 0.115 * info->at(1).diameter;
			break;
		case 5: // half turn about the model z axis
			r.pose.R = r.pose.R * Eigen::Vector3d(-1, -1, 1).asDiagonal();
			break;
		case 6: { // a duplicate with a lower score: still F1 = 1
			ResultRow dup = r;
			dup.score = 0.4;
			rows.push_back(dup);
			break;
		}
		case 8: { // a wrong pose scored above the right one takes the instance
			ResultRow wrong = r;
			wrong.score = 2.0;
			wrong.pose.t.z() += 100;
			rows.push_back(wrong);
			break;
		}
		case 9: // missed
			continue;
		case 10: { // eggbox: its own symmetry, so ADI still matches
			const Pose &s = info->at(10).symmetriesDiscrete.at(0);
			r.pose = r.pose * s;
			break;
		}
		default:
			break;
		}
		rows.push_back(r);
	}
	ASSERT_TRUE(writeResultsCsv(dir / "perturbed.csv", rows).ok());

	auto res = test::runIhf(evalArgs(dir / "perturbed.csv") +
				" --objects 1,5,6,8,9,10,11,12 --json " + q(dir / "r.json"));
	ASSERT_EQ(res.exitCode, 0) << res.output;
	const json doc = readJson(dir / "r.json");
	const std::vector<double> z = doc["z_values"];

	const json &o1 = objectEntry(doc, 1);
	for (size_t i = 0; i < z.size(); ++i)
		EXPECT_EQ(o1["f1"][i].get<double>(), z[i] >= 0.12 - 1e-9 ? 1.0 : 0.0) << "z " << z[i];
	EXPECT_DOUBLE_EQ(o1["mean_f1"].get<double>(), 4.0 / 11.0);
	EXPECT_EQ(o1["recall_0.1d"].get<double>(), 0.0);

	EXPECT_EQ(objectEntry(doc, 5)["mean_f1"].get<double>(), 0.0);
	EXPECT_EQ(objectEntry(doc, 6)["mean_f1"].get<double>(), 1.0);
	EXPECT_EQ(objectEntry(doc, 6)["num_estimates"], 2);
	EXPECT_EQ(objectEntry(doc, 8)["mean_f1"].get<double>(), 0.0);
	EXPECT_EQ(objectEntry(doc, 9)["num_estimates"], 0);
	EXPECT_EQ(objectEntry(doc, 9)["num_gt"], 1);
	EXPECT_EQ(objectEntry(doc, 9)["mean_f1"].get<double>(), 0.0);
	EXPECT_EQ(objectEntry(doc, 10)["metric"], "ADI");
	EXPECT_EQ(objectEntry(doc, 10)["mean_f1"].get<double>(), 1.0);
	EXPECT_EQ(objectEntry(doc, 11)["mean_f1"].get<double>(), 1.0);
	EXPECT_EQ(objectEntry(doc, 12)["mean_f1"].get<double>(), 1.0);
	EXPECT_DOUBLE_EQ(doc["mean"]["mean_f1"].get<double>(), (4.0 / 11.0 + 4.0) / 8.0);
	EXPECT_DOUBLE_EQ(doc["mean"]["recall_0.1d"].get<double>(), 4.0 / 8.0);
}

TEST(EvalCli, ObjectsAndTargetsSelectTheGroundTruth)
{
	const fs::path dir = test::freshTempDir("eval_cli_targets");
	ASSERT_TRUE(writeResultsCsv(dir / "gt.csv", groundTruthRows()).ok());

	auto res = test::runIhf(evalArgs(dir / "gt.csv") + " --objects 1,5 --json " +
				q(dir / "a.json"));
	ASSERT_EQ(res.exitCode, 0) << res.output;
	json doc = readJson(dir / "a.json");
	ASSERT_EQ(doc["objects"].size(), 2u);
	EXPECT_EQ(doc["mean"]["num_gt"], 2);

	// Boxes for objects 1 and 5 only: the other six objects have no ground
	// truth and their estimates are ignored.
	std::vector<Detection> boxes(2);
	boxes[0] = {2, 3, 1, 1.0, {10, 10, 50, 50}, 0};
	boxes[1] = {2, 3, 5, 1.0, {10, 10, 50, 50}, 0};
	ASSERT_TRUE(writeDetections(dir / "boxes.json", boxes).ok());
	res = test::runIhf(evalArgs(dir / "gt.csv") + " --targets " + q(dir / "boxes.json") +
			   " --json " + q(dir / "b.json"));
	ASSERT_EQ(res.exitCode, 0) << res.output;
	doc = readJson(dir / "b.json");
	ASSERT_EQ(doc["objects"].size(), 8u);
	EXPECT_EQ(doc["mean"]["num_gt"], 2);
	EXPECT_EQ(doc["mean"]["num_ignored"], 6);
	EXPECT_EQ(objectEntry(doc, 1)["mean_f1"].get<double>(), 1.0);
	EXPECT_EQ(objectEntry(doc, 6)["num_gt"], 0);
	EXPECT_DOUBLE_EQ(doc["mean"]["mean_f1"].get<double>(), 2.0 / 8.0);
}

TEST(EvalCli, VisibleSurfaceScoresTheTruthOneAndNeedsTheDepth)
{
	const fs::path dir = test::freshTempDir("eval_cli_vsd");
	auto info = readModelsInfo(test::lmoDir() / "models" / "models_info.json");
	ASSERT_TRUE(info.ok());
	std::vector<ResultRow> rows = groundTruthRows();
	for (ResultRow &r : rows)
		if (r.objId == 1) // beside the truth: no visible pixel shared
			r.pose.t.x() += 1.5 * info->at(1).diameter;
	ASSERT_TRUE(writeResultsCsv(dir / "rows.csv", rows).ok());

	auto res = test::runIhf(evalArgs(dir / "rows.csv") + " --vsd --json " + q(dir / "report.json"));
	ASSERT_EQ(res.exitCode, 0) << res.output;
	EXPECT_NE(res.output.find("AR_VSD"), std::string::npos) << res.output;
	const json doc = readJson(dir / "report.json");
	for (int id : kObjects)
		EXPECT_NEAR(objectEntry(doc, id)["ar_vsd"].get<double>(), id == 1 ? 0.0 : 1.0, 1e-12)
			<< "object " << id;
	EXPECT_NEAR(doc["mean"]["ar_vsd"].get<double>(), 7.0 / 8.0, 1e-12);
	EXPECT_EQ(doc["vsd"]["delta_mm"].get<double>(), 15.0);
	for (const json &e : doc["estimates"])
		EXPECT_NEAR(e["vsd_share"].get<double>(), e["obj_id"] == 1 ? 0.0 : 1.0, 1e-12);

	// Without --vsd nothing of it is reported.
	res = test::runIhf(evalArgs(dir / "rows.csv") + " --json " + q(dir / "plain.json"));
	ASSERT_EQ(res.exitCode, 0) << res.output;
	EXPECT_EQ(res.output.find("AR_VSD"), std::string::npos) << res.output;
	const json plain = readJson(dir / "plain.json");
	EXPECT_FALSE(plain.contains("vsd"));
	EXPECT_FALSE(plain["mean"].contains("ar_vsd"));
	EXPECT_FALSE(objectEntry(plain, 5).contains("ar_vsd"));

	// A split without its depth images: the missing image is named.
	const fs::path ds = dir / "ds";
	fs::create_directories(ds / "test" / "000002");
	fs::copy_file(test::lmoDir() / "camera.json", ds / "camera.json");
	fs::create_directory_symlink(test::lmoDir() / "models", ds / "models");
	for (const char *file : {"scene_camera.json", "scene_gt.json"})
		fs::copy_file(test::lmoDir() / "test" / "000002" / file, ds / "test" / "000002" / file);
	res = test::runIhf("eval --dataset " + q(ds) + " --results " + q(dir / "rows.csv") + " --vsd");
	EXPECT_EQ(res.exitCode, 1) << res.output;
	EXPECT_NE(res.output.find((ds / "test" / "000002" / "depth").string()), std::string::npos) << res.output;
	// The same split scores without --vsd.
	res = test::runIhf("eval --dataset " + q(ds) + " --results " + q(dir / "rows.csv"));
	EXPECT_EQ(res.exitCode, 0) << res.output;
}

// Runs eval expecting exit 1, a message containing every `needles`, and no
// JSON output left behind.
void expectFailure(const std::string &args, const fs::path &dir,
		   const std::vector<std::string> &needles)
{
	const fs::path out = dir / "never.json";
	auto res = test::runIhf(args + " --json " + q(out));
	EXPECT_EQ(res.exitCode, 1) << args << "\n" << res.output;
	for (const std::string &n : needles)
		EXPECT_NE(res.output.find(n), std::string::npos) << "no \"" << n << "\" in: " << res.output;
	EXPECT_FALSE(fs::exists(out));
}

TEST(EvalCli, BadInputsExitOneNamingTheFile)
{
	const fs::path dir = test::freshTempDir("eval_cli_bad");

	expectFailure(evalArgs(dir / "missing.csv"), dir, {"missing.csv"});

	{
		std::ofstream f(dir / "bad.csv");
		f << "scene_id,im_id,obj_id,score,R,t,time\n"
		  << "2,3,1,high,1 0 0 0 1 0 0 0 1,0 0 500,0.1\n";
	}
	expectFailure(evalArgs(dir / "bad.csv"), dir, {"bad.csv", "score"});

	std::vector<ResultRow> rows = groundTruthRows();
	rows[0].objId = 99;
	ASSERT_TRUE(writeResultsCsv(dir / "obj99.csv", rows).ok());
	expectFailure(evalArgs(dir / "obj99.csv"), dir, {"obj99.csv", "obj_id 99", "models_info.json"});

	rows = groundTruthRows();
	rows[0].imId = 4;
	ASSERT_TRUE(writeResultsCsv(dir / "im4.csv", rows).ok());
	expectFailure(evalArgs(dir / "im4.csv"), dir, {"im4.csv", "im_id 4", "not in split"});

	ASSERT_TRUE(writeResultsCsv(dir / "gt.csv", groundTruthRows()).ok());
	expectFailure(evalArgs(dir / "gt.csv") + " --objects 1,13", dir,
		      {"object 13", "models_info.json"});
	expectFailure("eval --dataset " + q(dir / "nowhere") + " --results " + q(dir / "gt.csv"),
		      dir, {"nowhere"});
	expectFailure(evalArgs(dir / "gt.csv") + " --targets " + q(dir / "nope.json"), dir,
		      {"nope.json"});

	// A dataset whose scene_gt.json lacks a field.
	const fs::path ds = dir / "ds";
	fs::create_directories(ds / "test" / "000002");
	fs::copy_file(test::lmoDir() / "camera.json", ds / "camera.json");
	fs::create_directory_symlink(test::lmoDir() / "models", ds / "models");
	fs::copy_file(test::lmoDir() / "test" / "000002" / "scene_camera.json",
		      ds / "test" / "000002" / "scene_camera.json");
	{
		std::ofstream f(ds / "test" / "000002" / "scene_gt.json");
		f << R"({"3": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "obj_id": 1}]})";
	}
	expectFailure("eval --dataset " + q(ds) + " --results " + q(dir / "gt.csv"), dir,
		      {"scene_gt.json", "cam_t_m2c"});
}

TEST(EvalCli, UsageErrorsExitTwo)
{
	EXPECT_EQ(test::runIhf("eval").exitCode, 2);
	EXPECT_EQ(test::runIhf("eval --dataset " + q(test::lmoDir())).exitCode, 2);
	EXPECT_EQ(test::runIhf("eval --dataset x --results y --objects one").exitCode, 2);
	EXPECT_EQ(test::runIhf("eval --dataset x --results y --objects 0").exitCode, 2);
	EXPECT_EQ(test::runIhf("eval --dataset x --results y --bogus").exitCode, 2);
	auto help = test::runIhf("eval --help");
	EXPECT_EQ(help.exitCode, 0);
	EXPECT_NE(help.output.find("--results"), std::string::npos);
	EXPECT_NE(help.output.find("--plot"), std::string::npos);
}

} // namespace
} // namespace ihf
