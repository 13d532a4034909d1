// SPDX-License-Identifier: MIT
// `ihf estimate` reports the runtime: per-stage times, budget counters and
// arena use on stderr and with --stats-json; the [budget] key of the
// configuration is read and checked; --trace writes every hypothesis and,
// for a nearly symmetric object, every comparison with a rival turn.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/model/forest_file.h"
#include "tests/runtime/small_model.h"

namespace ihf {
namespace {

class EstimateCli : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		dir_ = new std::filesystem::path(test::freshTempDir("estimate_cli"));
		test::SmallModel duck = test::trainSmallModel(9, 5, 20, 2);
		ASSERT_TRUE(duck.model);
		ASSERT_TRUE(saveModelFile(*dir_ / "duck.ihf", duck.model->params(), duck.model->mesh(),
					  duck.model->forest())
				    .ok());
		// The real frame's duck, twice (a frame of two boxes), and a box
		// for an object without a forest.
		std::ofstream boxes(*dir_ / "boxes.json");
		boxes << R"([{"scene_id": 2, "image_id": 3, "category_id": 9, "score": 1, "bbox": [333, 298, 64, 49], "time": 0},
			     {"scene_id": 2, "image_id": 3, "category_id": 9, "score": 1, "bbox": [335, 300, 62, 47], "time": 0},
			     {"scene_id": 2, "image_id": 3, "category_id": 5, "score": 1, "bbox": [376, 226, 60, 91], "time": 0}])";
	}
	static void TearDownTestSuite() { delete dir_; }

	static std::string args(const std::string &extra)
	{
		return "estimate --dataset '" + test::lmoDir().string() + "' --boxes '" + (*dir_ / "boxes.json").string() +
		       "' --forest 9='" + (*dir_ / "duck.ihf").string() + "' --out '" + (*dir_ / "r.csv").string() +
		       "' --quiet " + extra;
	}

	static std::filesystem::path *dir_;
};

std::filesystem::path *EstimateCli::dir_ = nullptr;

TEST_F(EstimateCli, ReportsStagesBudgetAndArena)
{
	const auto json = *dir_ / "stats.json";
	// One vote pass per iteration and one ICP polish per box, on one thread
	// (on more, a polish's cloud is charged to ICP), so that the stage calls
	// below can be counted exactly.
	const auto cfg = *dir_ / "single_pass.toml";
	// No re-search, so that the polishes can be counted.
	std::ofstream(cfg) << "[refinement]\ndepth_windows = 0\nresearch_rounds = 0\n[icp]\ncandidates = 1\nforest_bests = "
			      "false\n";
	auto r = test::runIhf(args("--iterations 1 --budget-ms 0 --threads 1 --config '" + cfg.string() + "' --stats-json '" +
				   json.string() + "'"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("time per stage"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("arena used"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("no frame budget: 1 frames, 2 boxes, 2 refinement iterations"), std::string::npos)
		<< r.output;

	std::ifstream in(json);
	ASSERT_TRUE(in.good());
	auto j = nlohmann::json::parse(in);
	EXPECT_EQ(j["budget"]["boxes"], 2);
	EXPECT_EQ(j["budget"]["frames"], 1);
	EXPECT_EQ(j["budget"]["tight_boxes"], 0); // no budget
	EXPECT_EQ(j["budget"]["short_boxes"], 0);
	EXPECT_EQ(j["budget"]["lean_search_boxes"], 0);
	EXPECT_EQ(j["budget"]["refinement_iterations"], 2);
	EXPECT_EQ(j["budget"]["researches"], 0);
	EXPECT_EQ(j["stages"]["ibs_fit"]["calls"], 4);   // 2 boxes x (k = 0, 1)
	// and one for each ICP: the polish's and the two best half-turns'
	EXPECT_EQ(j["stages"]["cloud"]["calls"], 10);
	EXPECT_EQ(j["stages"]["icp"]["calls"], 2);
	EXPECT_EQ(j["stages"]["half_turns"]["calls"], 2); // one polished hypothesis per box
	EXPECT_EQ(j["box_ms"]["count"], 2);
	const size_t used = j["arena"]["used_bytes"], capacity = j["arena"]["capacity_bytes"];
	EXPECT_GT(used, static_cast<size_t>(j["arena"]["persistent_bytes"]));
	EXPECT_LE(used, capacity);
	EXPECT_GT(j["limits_used"]["votes"][0].get<int>(), 0);
}

// --box-kind: what the boxes bound selects the score's weights, reported
// with the stats; a kind it does not know is a usage error.
TEST_F(EstimateCli, TheBoxKindSelectsTheScoreWeights)
{
	const auto json = *dir_ / "kind.json";
	auto r = test::runIhf(args("--iterations 0 --budget-ms 0 --threads 1 --box-kind modal --config '" +
				   (test::sourceDir() / "config" / "estimate.toml").string() + "' --stats-json '" +
				   json.string() + "'"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("boxes taken as modal: occluded weight 0.20, box power 1.00, occluded side 0.50"),
		  std::string::npos)
		<< r.output;
	std::ifstream in(json);
	ASSERT_TRUE(in.good());
	auto j = nlohmann::json::parse(in);
	EXPECT_EQ(j["score"]["box_kind"], "modal");
	EXPECT_FLOAT_EQ(j["score"]["occluded_weight"].get<float>(), 0.2f);
	EXPECT_FLOAT_EQ(j["score"]["box_weight"].get<float>(), 1.0f);
	EXPECT_FLOAT_EQ(j["score"]["box_occluded_side"].get<float>(), 0.5f);

	r = test::runIhf(args("--iterations 0 --budget-ms 0 --threads 1 --stats-json '" + json.string() + "'"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("boxes taken as amodal: occluded weight 0.10, box power 1.50, occluded side 0.00"),
		  std::string::npos)
		<< r.output;

	r = test::runIhf(args("--box-kind visible"));
	EXPECT_NE(r.exitCode, 0);
	EXPECT_NE(r.output.find("--box-kind"), std::string::npos) << r.output;
}

// --trace: per box the truth's score ("given"), every scored hypothesis,
// then the result, whose pose is the best-scoring hypothesis and whose
// confidence is the CSV's score.
TEST_F(EstimateCli, TheTraceEndsEachBoxWithItsResult)
{
	const auto trace = *dir_ / "trace.jsonl";
	auto r = test::runIhf(args("--iterations 1 --budget-ms 0 --threads 1 --trace '" + trace.string() + "'"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	std::ifstream in(trace);
	ASSERT_TRUE(in.good());
	std::vector<nlohmann::json> results;
	int givens = 0, hypotheses = 0;
	double best = -1;
	for (std::string line; std::getline(in, line);) {
		const auto j = nlohmann::json::parse(line);
		const std::string stage = j["stage"];
		if (stage == "votes" || stage == "comparison")
			continue;
		if (stage == "given") {
			++givens;
		} else if (stage == "result") {
			EXPECT_GT(hypotheses, 0);
			EXPECT_NEAR(j["score"].get<double>(), best, 1e-4) << line;
			results.push_back(j);
			hypotheses = 0;
			best = -1;
		} else {
			++hypotheses;
			best = std::max(best, j["score"].get<double>());
		}
	}
	EXPECT_EQ(hypotheses, 0); // nothing after the last result
	EXPECT_EQ(givens, 2);     // the duck's truth, once per box
	ASSERT_EQ(results.size(), 2u);

	std::ifstream csv(*dir_ / "r.csv");
	std::string header, row;
	std::getline(csv, header);
	for (const nlohmann::json &j : results) {
		ASSERT_TRUE(std::getline(csv, row));
		// scene_id,im_id,obj_id,score,R,t,time
		std::vector<std::string> f;
		for (size_t a = 0, b; a <= row.size(); a = b + 1) {
			b = row.find(',', a);
			if (b == std::string::npos)
				b = row.size();
			f.push_back(row.substr(a, b - a));
		}
		ASSERT_GE(f.size(), 4u) << row;
		EXPECT_TRUE(j["found"].get<bool>());
		EXPECT_NEAR(std::stod(f[3]), j["confidence"].get<double>(), 1e-4) << row;
		EXPECT_LE(j["confidence"].get<double>(), j["score"].get<double>() + 1e-6);
		EXPECT_GE(j["margin"].get<double>(), 0.0);
	}
}

TEST_F(EstimateCli, BudgetFromTheConfiguration)
{
	const auto cfg = *dir_ / "tiny_budget.toml";
	std::ofstream(cfg) << "[budget]\nestimation_budget_ms = 0.01\n";
	auto r = test::runIhf(args("--iterations 3 --config '" + cfg.string() + "'"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	// Far too little time: both boxes keep their initial registration, which
	// alone overran; the warm-up said so before the first frame.
	EXPECT_NE(r.output.find("budget 0.01 ms per frame: 1 frames, 2 boxes (2 tight, 2 short, 2 lean search), 0 refinement iterations, 0 re-searches (0 better, 2 "
				"left out), 2 boxes cut short, 2 ICP skipped, 1 frame overruns, 2 box overruns (2 already in the initial registration)"),
		  std::string::npos)
		<< r.output;
	EXPECT_NE(r.output.find("more than the 0.01 ms frame budget; boxes that large will overrun"), std::string::npos)
		<< r.output;
}

TEST_F(EstimateCli, ABadBudgetValueNamesFileAndKey)
{
	const auto cfg = *dir_ / "bad_budget.toml";
	std::ofstream(cfg) << "[budget]\nestimation_budget_ms = \"fast\"\n";
	auto r = test::runIhf(args("--config '" + cfg.string() + "'"));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("bad_budget.toml"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("estimation_budget_ms"), std::string::npos) << r.output;
	// Out of range: the tight profile's threshold cannot be negative.
	std::ofstream(cfg) << "[tight]\nbelow_ms = -5.0\n";
	r = test::runIhf(args("--config '" + cfg.string() + "'"));
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("tight.below_ms"), std::string::npos) << r.output;
}

// Estimation needs no ground truth: on a copy of the LM-O frame with only
// camera.json, scene_camera.json and the depth image (as a BOP test split or
// a user's own scenes), and on one with partial ground truth (scene_gt.json
// without the box's object, scene_gt_info.json without px_count_valid), the
// CSV is the same, byte for byte, as on the original. The trace says it has
// no truth to compare with; `ihf eval` still requires scene_gt.json.
TEST_F(EstimateCli, NeedsNoGroundTruth)
{
	namespace fs = std::filesystem;
	const fs::path bare = *dir_ / "lmo_no_gt", partial = *dir_ / "lmo_partial_gt";
	const fs::path scene = fs::path("test") / "000002";
	for (const fs::path &root : {bare, partial}) {
		fs::remove_all(root);
		fs::create_directories(root / scene / "depth");
		fs::create_directories(root / "models");
		fs::copy_file(test::lmoDir() / "camera.json", root / "camera.json");
		fs::copy_file(test::lmoDir() / "models" / "models_info.json", root / "models" / "models_info.json");
		fs::copy_file(test::lmoDir() / scene / "scene_camera.json", root / scene / "scene_camera.json");
		fs::copy_file(test::lmoDir() / scene / "depth" / "000003.png", root / scene / "depth" / "000003.png");
	}
	ASSERT_FALSE(fs::exists(bare / scene / "scene_gt.json"));
	// Ground truth of other objects only, and a gt_info entry per instance
	// without px_count_valid.
	std::ofstream(partial / scene / "scene_gt.json")
		<< R"({"3": [{"cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [0, 0, 900], "obj_id": 5}]})";
	std::ofstream(partial / scene / "scene_gt_info.json")
		<< R"({"3": [{"bbox_obj": [376, 226, 60, 91], "bbox_visib": [376, 226, 60, 91], "px_count_all": 4000,)"
		   R"( "px_count_visib": 3000, "visib_fract": 0.75}]})";

	auto estimate = [&](const fs::path &dataset, const std::string &csv, const std::string &extra) {
		return test::runIhf("estimate --dataset '" + dataset.string() + "' --boxes '" +
				    (*dir_ / "boxes.json").string() + "' --forest 9='" + (*dir_ / "duck.ihf").string() +
				    "' --out '" + (*dir_ / csv).string() +
				    "' --quiet --no-time --iterations 1 --budget-ms 0 --threads 1 " + extra);
	};
	auto bytes = [&](const std::string &csv) {
		std::ifstream in(*dir_ / csv, std::ios::binary);
		return std::string(std::istreambuf_iterator<char>(in), {});
	};
	auto r = estimate(test::lmoDir(), "with_gt.csv", "");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const std::string want = bytes("with_gt.csv");
	// Both duck boxes have a pose, with the unknown time.
	ASSERT_EQ(std::count(want.begin(), want.end(), '\n'), 3) << want;
	EXPECT_NE(want.find(",-1\n"), std::string::npos) << want;

	const fs::path trace = *dir_ / "no_gt_trace.jsonl";
	r = estimate(bare, "no_gt.csv", "--trace '" + trace.string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_EQ(bytes("no_gt.csv"), want);
	EXPECT_NE(r.output.find("scene 2 has no ground truth to trace against"), std::string::npos) << r.output;
	int noTruth = 0, givens = 0, votes = 0;
	std::ifstream in(trace);
	for (std::string line; std::getline(in, line);) {
		const auto j = nlohmann::json::parse(line);
		const std::string stage = j["stage"];
		if (stage == "no_truth") {
			++noTruth;
			EXPECT_NE(j["reason"].get<std::string>().find("scene_gt.json"), std::string::npos) << line;
		}
		givens += stage == "given";
		votes += stage == "votes";
	}
	EXPECT_EQ(noTruth, 2); // once per duck box
	EXPECT_EQ(givens, 0);
	EXPECT_EQ(votes, 0);

	r = estimate(partial, "partial_gt.csv", "--trace '" + trace.string() + "'");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_EQ(bytes("partial_gt.csv"), want);
	std::ifstream partialTrace(trace);
	const std::string traced(std::istreambuf_iterator<char>(partialTrace), {});
	EXPECT_NE(traced.find(R"("stage":"no_truth","reason":"scene_gt.json has no object 9 in image 3")"),
		  std::string::npos)
		<< traced;

	// Evaluation compares with the ground truth, so it needs it.
	r = test::runIhf("eval --dataset '" + bare.string() + "' --results '" + (*dir_ / "no_gt.csv").string() + "'");
	EXPECT_EQ(r.exitCode, 1) << r.output;
	EXPECT_NE(r.output.find("scene_gt.json"), std::string::npos) << r.output;
}

// --trace on a nearly symmetric object (a cup, trained small with its
// near-symmetry): each box's comparisons of the best with its turns about
// the cup's axis and its end-over-end turn, with the pixels that spoke for
// each, before its result.
TEST_F(EstimateCli, TheTraceListsTheTurnsComparedForANearlySymmetricObject)
{
	const auto dir = *dir_ / "cup";
	std::filesystem::create_directories(dir);
	const auto q = test::quoted;
	auto r = test::runIhf("synth --make-object cup --id 31 --models " + q(dir / "m"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	std::ofstream(dir / "train.toml") << "[views]\nviewpoints = 40\ninplane_steps = 2\n"
					     "[scales]\nfactors = [1.0]\nparts_per_image = 8\noccluded_views = 0.0\n";
	r = test::runIhf("train --model " + q(dir / "m" / "obj_000031.ply") + " --out " + q(dir / "cup.ihf") +
			 " --config " + q(dir / "train.toml"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	ASSERT_NE(r.output.find("near-symmetry: any turn"), std::string::npos) << r.output;
	r = test::runIhf("synth --models " + q(dir / "m") +
			 " --objects 31 --images 2 --seed 5 --distance 650:800 --quiet --out " + q(dir / "syn"));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto trace = dir / "trace.jsonl";
	r = test::runIhf("estimate --dataset " + q(dir / "syn") + " --boxes " + q(dir / "syn" / "boxes.json") +
			 " --forest 31=" + q(dir / "cup.ihf") + " --out " + q(dir / "r.csv") +
			 " --budget-ms 0 --threads 1 --quiet --trace " + q(trace));
	ASSERT_EQ(r.exitCode, 0) << r.output;

	std::ifstream in(trace);
	ASSERT_TRUE(in.good());
	int results = 0, turns = 0;
	for (std::string line; std::getline(in, line);) {
		const auto j = nlohmann::json::parse(line);
		if (j["stage"] == "result") {
			EXPECT_GT(turns, 0) << "no turn compared before this result: " << line;
			++results;
			turns = 0;
			continue;
		}
		if (j["stage"] != "comparison")
			continue;
		const std::string kind = j["kind"];
		EXPECT_TRUE(kind == "turn" || kind == "end_over_end" || kind == "close_rival") << line;
		ASSERT_EQ(j["R"].size(), 9u) << line;
		ASSERT_EQ(j["t"].size(), 3u) << line;
		const int forBest = j["for_best"], forRival = j["for_rival"], informative = j["informative"];
		EXPECT_EQ(forBest + forRival, informative) << line;
		EXPECT_LE(informative, j["differing"].get<int>()) << line;
		EXPECT_GT(j["min_pixels"].get<int>(), 0) << line;
		// A polished rival carries the score the polish gave it.
		ASSERT_EQ(j.contains("score"), j["polished"].get<bool>()) << line;
		if (j.contains("score")) {
			EXPECT_GT(j["score"].get<double>(), 0.0) << line;
			EXPECT_LE(j["score"].get<double>(), 1.0) << line;
		}
		if (kind == "turn") {
			++turns;
			EXPECT_GT(std::abs(j["axis"][2].get<double>()), 0.99) << "about the cup's axis: " << line;
		}
		if (kind == "end_over_end")
			EXPECT_LT(std::abs(j["axis"][2].get<double>()), 0.01) << "square to the cup's axis: " << line;
	}
	EXPECT_EQ(results, 2);
}

} // namespace
} // namespace ihf
