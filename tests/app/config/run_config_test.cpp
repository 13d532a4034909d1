// SPDX-License-Identifier: MIT
// config/device.toml: values, relative paths resolved against the file's
// folder, and errors that name the file and the key.

#include <fstream>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/geometry/ply_loader.h"
#include "core/model/object_model.h"
#include "firmware_app/config/pipeline_config.h"
#include "tests/common/test_paths.h"

namespace ihf::app {
namespace {

namespace fs = std::filesystem;

fs::path writeConfig(const std::string &name, const std::string &text)
{
	const fs::path dir = test::freshTempDir("run_config_" + name);
	std::ofstream(dir / "device.toml") << text;
	return dir / "device.toml";
}

TEST(RunConfig, ReadsEveryKeyAndResolvesRelativePaths)
{
	const fs::path file = writeConfig("all", R"(
[source]
uri = "recording:data/scene.rec"
pacing = "real_time"
speed = 2.0
timeout_ms = 250
max_retries = 7
retry_backoff_ms = 10
retry_backoff_max_ms = 80
[boxes]
input = "unix:run/ihf.sock"
timeout_ms = 40
kind = "modal"
[output]
poses = "file:out/poses.jsonl"
[objects]
20 = "forests/bunny.ihf"
5 = "/abs/can.ihf"
[estimate]
config = "estimate.toml"
iterations = 3
[tracking]
enabled = false
match_iou = 0.4
max_missed_frames = 9
max_defer_frames = 2
detect_min_ms = 12.5
refresh = false
min_score = 0.35
keep_share = 0.6
[run]
drop_frames_older_than_ms = 66.5
stats_interval_s = 2
max_frames = 100
)");
	auto s = loadRunConfig(file);
	ASSERT_TRUE(s.ok()) << s.error().message;
	const fs::path dir = file.parent_path();
	EXPECT_EQ(s->sourceUri, "recording:" + (dir / "data/scene.rec").string());
	EXPECT_TRUE(s->realTime);
	EXPECT_EQ(s->speed, 2.0);
	EXPECT_EQ(s->timeoutMs, 250);
	EXPECT_EQ(s->maxRetries, 7);
	EXPECT_EQ(s->retryBackoffMs, 10);
	EXPECT_EQ(s->retryBackoffMaxMs, 80);
	EXPECT_EQ(s->boxes, "unix:" + (dir / "run/ihf.sock").string());
	EXPECT_EQ(s->boxesTimeoutMs, 40);
	EXPECT_EQ(s->boxKind, BoxKind::kModal);
	EXPECT_EQ(s->poses, "file:" + (dir / "out/poses.jsonl").string());
	ASSERT_EQ(s->forests.size(), 2u);
	EXPECT_EQ(s->forests.at(20), dir / "forests/bunny.ihf");
	EXPECT_EQ(s->forests.at(5), fs::path("/abs/can.ihf"));
	EXPECT_EQ(s->estimateConfig, dir / "estimate.toml");
	EXPECT_EQ(s->iterations.value_or(-1), 3);
	EXPECT_FALSE(s->tracking.enabled);
	EXPECT_FLOAT_EQ(s->tracking.matchIou, 0.4f);
	EXPECT_EQ(s->tracking.maxMissedFrames, 9);
	EXPECT_EQ(s->tracking.maxDeferFrames, 2);
	EXPECT_FLOAT_EQ(s->tracking.detectMinMs, 12.5f);
	EXPECT_FALSE(s->tracking.refresh);
	EXPECT_FLOAT_EQ(s->tracking.minScore, 0.35f);
	EXPECT_FLOAT_EQ(s->tracking.keepShare, 0.6f);
	EXPECT_EQ(s->dropFramesOlderThanMs, 66.5);
	EXPECT_EQ(s->statsIntervalS, 2.0);
	EXPECT_EQ(s->maxFrames, 100);
}

TEST(RunConfig, DevicePathsStayAsGiven)
{
	auto s = loadRunConfig(writeConfig("v4l2", "[source]\nuri = \"v4l2:/dev/video0?format=y16\"\n"));
	ASSERT_TRUE(s.ok());
	EXPECT_EQ(s->sourceUri, "v4l2:/dev/video0?format=y16");
	EXPECT_EQ(s->boxes, "stdin");
	EXPECT_EQ(s->poses, "stdout");
	EXPECT_FALSE(s->boxKind.has_value()); // as the estimation config's
	EXPECT_FALSE(s->realTime);
}

TEST(RunConfig, ErrorsNameTheFileAndKey)
{
	auto typo = loadRunConfig(writeConfig("typo", "[source]\nurl = \"x\"\n"));
	ASSERT_FALSE(typo.ok());
	EXPECT_NE(typo.error().message.find("unknown key source.url"), std::string::npos) << typo.error().message;
	EXPECT_NE(typo.error().message.find("device.toml"), std::string::npos);

	auto pacing = loadRunConfig(writeConfig("pacing", "[source]\npacing = \"fast\"\n"));
	ASSERT_FALSE(pacing.ok());
	EXPECT_NE(pacing.error().message.find("source.pacing"), std::string::npos) << pacing.error().message;

	auto obj = loadRunConfig(writeConfig("obj", "[objects]\nbunny = \"b.ihf\"\n"));
	ASSERT_FALSE(obj.ok());
	EXPECT_NE(obj.error().message.find("objects.bunny"), std::string::npos) << obj.error().message;

	auto kind = loadRunConfig(writeConfig("kind", "[boxes]\nkind = \"visible\"\n"));
	ASSERT_FALSE(kind.ok());
	EXPECT_NE(kind.error().message.find("boxes.kind"), std::string::npos) << kind.error().message;

	auto range = loadRunConfig(writeConfig("range", "[source]\nretry_backoff_ms = 100\nretry_backoff_max_ms = 10\n"));
	ASSERT_FALSE(range.ok());
	EXPECT_NE(range.error().message.find("source.retry_backoff_max_ms"), std::string::npos);

	auto defer = loadRunConfig(writeConfig("defer", "[tracking]\nmax_defer_frames = 0\n"));
	ASSERT_FALSE(defer.ok());
	EXPECT_NE(defer.error().message.find("tracking.max_defer_frames"), std::string::npos);

	auto section = loadRunConfig(writeConfig("section", "[sources]\n"));
	ASSERT_FALSE(section.ok());
	EXPECT_NE(section.error().message.find("unknown section [sources]"), std::string::npos);
}

// TOML integers are 64-bit; a value the setting cannot hold is a range
// error, not wrapped (4294968296 was taken as 1000), and a number outside
// the float range is refused too (found by tests/fuzz/fuzz_toml_config).
TEST(RunConfig, ValuesBeyondTheSettingsTypeAreRangeErrors)
{
	auto wrapped = loadRunConfig(writeConfig("wrapped", "[source]\ntimeout_ms = 4294968296\n"));
	ASSERT_FALSE(wrapped.ok());
	EXPECT_EQ(wrapped.error().code, Errc::kOutOfRange);
	EXPECT_NE(wrapped.error().message.find("device.toml: source.timeout_ms: 4294968296 is out of range "
					       "[-2147483648, 2147483647]"),
		  std::string::npos)
		<< wrapped.error().message;

	auto narrow = loadEstimateConfig(writeConfig("narrow", "[budget]\nestimation_budget_ms = 1e300\n"));
	ASSERT_FALSE(narrow.ok());
	EXPECT_EQ(narrow.error().code, Errc::kOutOfRange);
	EXPECT_NE(narrow.error().message.find("budget.estimation_budget_ms: "), std::string::npos) << narrow.error().message;
	EXPECT_NE(narrow.error().message.find("is outside the range of a 32-bit float"), std::string::npos)
		<< narrow.error().message;

	auto bins = loadTrainConfig(writeConfig("bins", "[hocp]\nn_phi = 1073741828\n"));
	ASSERT_FALSE(bins.ok());
	EXPECT_EQ(bins.error().code, Errc::kOutOfRange);
	EXPECT_NE(bins.error().message.find("hocp: bin counts n_r 4 x n_theta 8 x n_phi 1073741828"), std::string::npos)
		<< bins.error().message;
}

TEST(RunConfig, TheBundledDeviceConfigLoads)
{
	auto s = loadRunConfig(test::sourceDir() / "config" / "device.toml");
	ASSERT_TRUE(s.ok()) << s.error().message;
	EXPECT_FALSE(s->sourceUri.empty());
	EXPECT_FALSE(s->forests.empty());
	// Its [tracking] keys are the code's defaults, which ihf estimate
	// --sequence uses.
	const TrackerConfig d;
	EXPECT_EQ(s->tracking.enabled, d.enabled);
	EXPECT_EQ(s->tracking.maxMissedFrames, d.maxMissedFrames);
	EXPECT_EQ(s->tracking.maxDeferFrames, d.maxDeferFrames);
	EXPECT_EQ(s->tracking.detectMinMs, d.detectMinMs);
}

// Offline estimation measures the full method: no budget unless configured,
// and the bundled estimation config agrees with the library's defaults.
TEST(EstimateConfig, OfflineDefaultsHaveNoBudgetAndMatchTheBundledConfig)
{
	auto none = loadEstimateConfig({});
	ASSERT_TRUE(none.ok());
	EXPECT_EQ(none->estimator.frameBudgetMs, 0.0f);
	// The bundled config agrees with the defaults: ConfigSchema's
	// TheShippedFilesHoldTheUserSettingsAtTheirDefaults, key by key.
	auto bundled = loadEstimateConfig(test::sourceDir() / "config" / "estimate.toml");
	ASSERT_TRUE(bundled.ok()) << bundled.error().message;
	EXPECT_EQ(bundled->estimator.frameBudgetMs, 0.0f);
}

TEST(EstimateConfig, OutOfRangeValuesNameTheFileAndKey)
{
	const fs::path dir = test::freshTempDir("estimate_config_range");
	for (const auto &[text, key] : std::vector<std::pair<std::string, std::string>>{
		     {"[view_search]\nkeep = 0\n", "view_search.keep"},
		     {"[view_search]\nedge_insets = 9\n", "view_search.edge_insets"},
		     {"[view_search]\nedge_inset_share = 0.6\n", "view_search.edge_inset_share"},
		     {"[view_search]\ncentre_shift_share = -0.1\n", "view_search.centre_shift_share"},
		     {"[budget.view_search]\ncentre_shift_share = 0.6\n", "budget.view_search.centre_shift_share"},
		     {"[view_search]\npoints = 1000\n", "view_search.points"},
		     {"[view_search]\ncoarse_keep = 5000\n", "view_search.coarse_keep"},
		     {"[view_search]\ndepth_centres = 5\n", "view_search.depth_centres"},
		     {"[view_search]\nanchor_share = 0\n", "view_search.anchor_share"},
		     {"[view_search]\ndepth_centre_width = -0.5\n", "view_search.depth_centre_width"},
		     {"[view_search]\nlateral_step_mm = -1\n", "view_search.lateral_step_mm"},
		     {"[view_search]\nrotation_step_deg = 50\n", "view_search.rotation_step_deg"},
		     {"[view_search]\nrefine_top = 65\n", "view_search.refine_top"},
		     {"[budget.view_search]\nrefine_top = 0\n", "budget.view_search.refine_top"},
		     {"[budget.view_search]\nrotation_step_deg = -1\n", "budget.view_search.rotation_step_deg"},
		     {"[budget.view_search]\ncoarse_points = 300\n", "budget.view_search.coarse_points"},
		     {"[budget.view_search]\ncoarse_keep = 0\n", "budget.view_search.coarse_keep"},
		     {"[budget.view_search]\ndepth_centres = 5\n", "budget.view_search.depth_centres"},
		     {"[budget.view_search]\ndepth_centre_width = 11\n", "budget.view_search.depth_centre_width"},
		     {"[budget]\npolish_rounds = -1\n", "budget.polish_rounds"},
		     {"[budget.view_search]\nviewpoints = 0\n", "budget.view_search.viewpoints"},
		     {"[lean]\nbelow_searches = -1\n", "lean.below_searches"},
		     {"[lean.view_search]\nrotation_step_deg = 46\n", "lean.view_search.rotation_step_deg"},
		     {"[lean.view_search]\ncoarse_points = 300\n", "lean.view_search.coarse_points"},
		     {"[budget.refinement]\niterations = -1\n", "budget.refinement.iterations"},
		     {"[budget.refinement]\ndepth_windows = -1\n", "budget.refinement.depth_windows"},
		     {"[budget.refinement]\ntarget_parts = 0\n", "budget.refinement.target_parts"},
		     {"[short.icp]\niterations = 0\n", "short.icp.iterations"},
		     {"[short]\nbelow_ms = -1\n", "short.below_ms"},
		     {"[score]\nbox_occluded_side = 1.5\n", "score.box_occluded_side"},
		     {"[score]\nbox_occluded_band_px = 0\n", "score.box_occluded_band_px"},
		     {"[score]\nbox_weight = -1\n", "score.box_weight"},
		     {"[modal_boxes.score]\nbox_weight = -1\n", "modal_boxes.score.box_weight"},
		     {"[modal_boxes.score]\noccluded_weight = -0.1\n", "modal_boxes.score.occluded_weight"},
		     {"[modal_boxes.score]\nbox_occluded_side = 2\n", "modal_boxes.score.box_occluded_side"},
		     {"[boxes]\nkind = \"visible\"\n", "boxes.kind"},
		     {"[short.score]\noccluded_weight = nan\n", "short.score.occluded_weight"},
		     {"[half_turns]\ncandidates = 5\n", "half_turns.candidates"},
		     {"[half_turns]\nkeep = 0\n", "half_turns.keep"},
		     {"[half_turns]\nscreen = 33\n", "half_turns.screen"},
		     {"[render_mesh]\nmax_error_mm = -1\n", "render_mesh.max_error_mm"},
		     {"[score]\nresidual_weight = 1.5\n", "score.residual_weight"},
		     {"[confidence]\ndistinct_share = 0\n", "confidence.distinct_share"},
		     {"[confidence]\nfull_margin = -0.1\n", "confidence.full_margin"},
		     {"[limits]\nmax_rivals = -1\n", "limits.max_rivals"},
		     {"[votes]\nrotation_modes = 0\n", "votes.rotation_modes"},
		     {"[votes]\nmax_shift_votes = -1\n", "votes.max_shift_votes"},
		     {"[limits]\nthreads = 9\n", "limits.threads"},
		     {"[limits]\nthreads = -1\n", "limits.threads"},
		     {"[iteration.refinement]\ntarget_parts = 0\n", "iteration.refinement.target_parts"},
		     {"[iteration.refinement]\nibs_max_points = -1\n", "iteration.refinement.ibs_max_points"},
		     {"[iteration.refinement]\nibs_cg_iterations = -1\n", "iteration.refinement.ibs_cg_iterations"},
		     {"[iteration.votes]\nmax_shift_votes = -1\n", "iteration.votes.max_shift_votes"},
		     {"[refinement]\nresearch_rounds = -1\n", "refinement.research_rounds"},
		     {"[refinement]\nresearch_polish = 17\n", "refinement.research_polish"},
		     {"[budget.refinement]\nresearch_rounds = -1\n", "budget.refinement.research_rounds"},
		     {"[refinement]\npsi1 = 1.1\npsi2 = 1.0\n", "refinement.psi1/psi2"}}) {
		std::ofstream(dir / "e.toml") << text;
		auto s = loadEstimateConfig(dir / "e.toml");
		ASSERT_FALSE(s.ok()) << text;
		EXPECT_NE(s.error().message.find(key), std::string::npos) << s.error().message;
		EXPECT_NE(s.error().message.find("e.toml"), std::string::npos) << s.error().message;
	}
}

// The kind of the given boxes selects the score's occlusion and box weights:
// [score]'s for amodal boxes (the default), [modal_boxes]' for modal ones,
// and switching back restores them. Only a box round the whole object has
// the view search place rotations by its size.
TEST(EstimateConfig, TheBoxKindSelectsTheScoreWeights)
{
	auto bundled = loadEstimateConfig(test::sourceDir() / "config" / "estimate.toml");
	ASSERT_TRUE(bundled.ok()) << bundled.error().message;
	EXPECT_EQ(bundled->boxKind, BoxKind::kAmodal);
	const ScoreConfig library;
	EXPECT_EQ(bundled->estimator.score.occludedWeight, library.occludedWeight);
	EXPECT_EQ(bundled->estimator.score.boxWeight, library.boxWeight);
	EXPECT_EQ(bundled->estimator.score.boxOccludedSide, library.boxOccludedSide);
	EXPECT_TRUE(bundled->estimator.views.boxSizeSearch);
	auto none = loadEstimateConfig({});
	ASSERT_TRUE(none.ok());
	EXPECT_EQ(none->modal.occludedWeight, bundled->modal.occludedWeight);
	EXPECT_EQ(none->modal.boxWeight, bundled->modal.boxWeight);
	EXPECT_EQ(none->modal.boxOccludedSide, bundled->modal.boxOccludedSide);

	EstimateSettings s = *bundled;
	useBoxKind(s, BoxKind::kModal);
	EXPECT_EQ(s.boxKind, BoxKind::kModal);
	EXPECT_EQ(s.estimator.score.occludedWeight, 0.2f);
	EXPECT_EQ(s.estimator.score.boxWeight, 1.0f);
	EXPECT_EQ(s.estimator.score.boxOccludedSide, 0.5f);
	EXPECT_EQ(s.estimator.score.inlierMm, bundled->estimator.score.inlierMm); // the rest as it was
	EXPECT_FALSE(s.estimator.views.boxSizeSearch);
	useBoxKind(s, BoxKind::kAmodal);
	EXPECT_TRUE(s.estimator.views.boxSizeSearch);
	EXPECT_EQ(s.estimator.score.occludedWeight, library.occludedWeight);
	EXPECT_EQ(s.estimator.score.boxWeight, library.boxWeight);
	EXPECT_EQ(s.estimator.score.boxOccludedSide, library.boxOccludedSide);

	// A file's own weights for either kind, and the kind chosen in it.
	const fs::path dir = test::freshTempDir("estimate_config_box_kind");
	std::ofstream(dir / "e.toml") << "[boxes]\nkind = \"modal\"\n[score]\noccluded_weight = 0.3\n"
					  "[modal_boxes.score]\noccluded_weight = 0.4\nbox_weight = 2.0\nbox_occluded_side = 0.25\n";
	auto own = loadEstimateConfig(dir / "e.toml");
	ASSERT_TRUE(own.ok()) << own.error().message;
	EXPECT_EQ(own->boxKind, BoxKind::kModal);
	EXPECT_EQ(own->estimator.score.occludedWeight, 0.4f);
	EXPECT_EQ(own->estimator.score.boxWeight, 2.0f);
	EXPECT_EQ(own->estimator.score.boxOccludedSide, 0.25f);
	useBoxKind(*own, BoxKind::kAmodal);
	EXPECT_EQ(own->estimator.score.occludedWeight, 0.3f);
	EXPECT_EQ(own->estimator.score.boxWeight, library.boxWeight);

	EXPECT_TRUE(parseBoxKind("amodal", "x").ok());
	auto bad = parseBoxKind("visible", "f.toml: boxes.kind");
	ASSERT_FALSE(bad.ok());
	EXPECT_NE(bad.error().message.find("f.toml: boxes.kind"), std::string::npos);
	EXPECT_NE(bad.error().message.find("visible"), std::string::npos);
}

// --paper: the paper's method alone (no ICP, view search or half-turns), its
// refinement iterations voting as its registration does.
TEST(EstimateConfig, ThePapersMethodDropsTheAdditions)
{
	auto settings = loadEstimateConfig(test::sourceDir() / "config" / "estimate.toml");
	ASSERT_TRUE(settings.ok()) << settings.error().message;
	EstimatorConfig e = settings->estimator;
	// The shipped config has them all on, and its iterations leaner.
	ASSERT_TRUE(e.icp);
	ASSERT_GT(e.views.inplane, 0);
	ASSERT_GT(e.halfTurns.candidates, 0);
	ASSERT_LT(forIterations(e).targetParts, e.targetParts);
	applyPapersMethod(e);
	EXPECT_FALSE(e.icp);
	EXPECT_EQ(e.views.inplane, 0);
	EXPECT_EQ(e.halfTurns.candidates, 0);
	const EstimatorConfig it = forIterations(e);
	EXPECT_EQ(it.targetParts, e.targetParts);
	EXPECT_EQ(it.ibsMaxPoints, e.ibsMaxPoints);
	EXPECT_EQ(it.ibsCgIterations, e.ibsCgIterations);
	EXPECT_EQ(it.maxShiftVotes, e.maxShiftVotes);
	EXPECT_EQ(e.iterations, settings->estimator.iterations); // k is the caller's
}

// View templates are built at load with the offline viewpoint count, or the
// budget's when the estimator runs inside a frame budget (the device).
TEST(EstimateConfig, PreparedModelHasTheBudgetsViewpointsInsideABudget)
{
	auto mesh = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
	ASSERT_TRUE(mesh.ok()) << mesh.error().message;
	auto settings = loadEstimateConfig({});
	ASSERT_TRUE(settings.ok());
	settings->viewTemplates.viewpoints = 40;
	settings->viewTemplates.budgetViewpoints = 20;
	settings->viewTemplates.pointsPerView = 16;
	settings->renderMeshErrorMm = 0;
	ModelParams params;
	params.diameter = 102.1;
	for (const float budgetMs : {0.0f, 33.0f}) {
		OwnedObjectModel model(params, *mesh, {});
		settings->estimator.frameBudgetMs = budgetMs;
		ASSERT_TRUE(prepareModel(model, *settings).ok());
		EXPECT_EQ(model.viewTemplates().viewpoints, budgetMs > 0 ? 20 : 40);
		EXPECT_EQ(model.viewTemplates().points.size(), size_t{16} * (budgetMs > 0 ? 20 : 40));
	}
}

} // namespace
} // namespace ihf::app
