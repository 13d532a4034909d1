// SPDX-License-Identifier: MIT
// `ihf eval`: scores a BOP results CSV against a dataset split's ground
// truth (F1 over z = 0.05..0.15 of the diameter, ADD for plain objects and
// ADI for symmetric ones, and with --vsd BOP's visible surface discrepancy;
// see core/eval/evaluation.h), prints a table and
// optionally writes JSON and a precision-recall plot. With --run-poses it
// says instead how close each pose line of `ihf run` on a recording of the
// dataset came to the truth (core/eval/run_pose_check.h); wrong poses are
// reported, not a failure.

#include <charconv>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "core/eval/eval_dataset.h"
#include "core/eval/eval_report_json.h"
#include "core/eval/eval_report_text.h"
#include "core/eval/pr_plot.h"
#include "core/eval/run_pose_check.h"
#include "core/eval/run_poses.h"
#include "firmware_app/commands/command.h"

namespace ihf::app {

namespace {

struct EvalOptions {
	std::string dataset;
	std::string split;
	std::string results;
	std::string runPoses;
	int scene = -1;
	std::vector<int> objects;
	std::string targets;
	std::string json;
	std::string plot;
	bool visibleSurface = false;
};

int fail(const std::string &message)
{
	std::fprintf(stderr, "ihf eval: %s\n", message.c_str());
	return kExitFailure;
}

int runEval(const EvalOptions &opt)
{
	// Refuse early, before any work or output.
	if (!opt.plot.empty() && !prPlotSupported())
		return fail("--plot: built without plotting support (libcairo2-dev)");

	Expected<BopDataset> dataset = BopDataset::open(opt.dataset, opt.split);
	if (!dataset)
		return fail(dataset.error().message);

	Expected<std::vector<ResultRow>> results = readResultsCsv(opt.results);
	if (!results)
		return fail(results.error().message);
	if (results->empty() && opt.objects.empty())
		return fail(opt.results + ": no result rows and no --objects: nothing to evaluate");

	EvalRequest request;
	request.objects = opt.objects;
	request.resultsFile = opt.results;
	request.visibleSurface = opt.visibleSurface;
	if (!opt.targets.empty()) {
		Expected<std::vector<Detection>> targets = readDetections(opt.targets);
		if (!targets)
			return fail(targets.error().message);
		request.targets = std::move(*targets);
		request.targetsFile = opt.targets;
	}

	Expected<EvalReport> report = evaluateOnDataset(*dataset, *results, request);
	if (!report)
		return fail(report.error().message);

	std::printf("ihf eval: %s, split %s, results %s\n", dataset->root().c_str(),
		    dataset->split().c_str(), opt.results.c_str());
	std::fputs(formatEvalTable(*report).c_str(), stdout);
	std::fflush(stdout);

	// Render before writing anything, so a drawing failure leaves no output.
	std::unique_ptr<RgbImage> plot;
	if (!opt.plot.empty()) {
		Expected<RgbImage> image = renderPrPlot(*report);
		if (!image)
			return fail(opt.plot + ": " + image.error().message);
		plot = std::make_unique<RgbImage>(std::move(*image));
	}
	if (!opt.json.empty()) {
		Status s = writeEvalReportJson(opt.json, *report);
		if (!s)
			return fail(s.error().message);
	}
	if (plot) {
		Status s = writePng8(opt.plot, plot->width, plot->height, 3, plot->pixels.data());
		if (!s)
			return fail(s.error().message);
	}
	return kExitOk;
}

int runEvalRunPoses(const EvalOptions &opt)
{
	Expected<BopDataset> dataset = BopDataset::open(opt.dataset, opt.split);
	if (!dataset)
		return fail(dataset.error().message);
	Expected<std::vector<RunPoseLine>> lines = readRunPoses(opt.runPoses);
	if (!lines)
		return fail(lines.error().message);

	RunPoseRequest request;
	request.sceneId = opt.scene;
	request.posesFile = opt.runPoses;
	Expected<RunPoseReport> report = checkRunPoses(*dataset, *lines, request);
	if (!report) {
		fail(report.error().message);
		return report.error().code == Errc::kInvalidArgument ? kExitUsage : kExitFailure;
	}
	std::printf("ihf eval: poses %s against the ground truth of %s, split %s, scene %d\n",
		    opt.runPoses.c_str(), dataset->root().c_str(), dataset->split().c_str(), report->sceneId);
	std::fputs(formatRunPoseTable(*report).c_str(), stdout);
	return kExitOk;
}

// CLI11's stock number checks print their whole range on bad input.
CLI::Validator objectIdValidator()
{
	return CLI::Validator(
		[](std::string &text) -> std::string {
			int id = 0;
			const char *end = text.data() + text.size();
			auto [ptr, ec] = std::from_chars(text.data(), end, id);
			if (ec != std::errc() || ptr != end || id <= 0)
				return "object ids are positive integers, got \"" + text + "\"";
			return {};
		},
		"OBJ_ID");
}

} // namespace

void addEvalCommand(CLI::App &root, Action &action)
{
	auto opt = std::make_shared<EvalOptions>();
	auto *cmd = root.add_subcommand(
		"eval",
		"Score pose estimates (BOP results CSV) against a dataset's ground truth: "
		"F1 at z = 0.05..0.15 of the diameter (ADD, ADI for symmetric objects); "
		"or, with --run-poses, how close each pose of `ihf run` came to it");
	cmd->add_option("--dataset", opt->dataset, "BOP dataset root (camera.json, models/, SPLIT/)")
		->required();
	cmd->add_option("--split", opt->split, "dataset split (default: test, val or train)");
	auto *results = cmd->add_option("--results", opt->results,
					"results CSV: scene_id,im_id,obj_id,score,R,t,time");
	auto *runPoses = cmd->add_option(
		"--run-poses", opt->runPoses,
		"pose lines of `ihf run` (JSON lines) on a recording of the dataset (`ihf record "
		"--from-bop`): each pose's rotation and translation error, right at ADD (ADI) <= 0.1 d");
	results->excludes(runPoses);
	cmd->add_option("--scene", opt->scene,
			"--run-poses: the recorded scene (needed when the split has several)")
		->check(CLI::NonNegativeNumber)
		->needs(runPoses);
	auto *objects = cmd->add_option("--objects", opt->objects,
					"object ids to evaluate, e.g. 1,5,6 (default: every object in the results)")
		->delimiter(',')
		->check(objectIdValidator());
	auto *targets = cmd->add_option("--targets", opt->targets,
					"BOP detection list: only ground truth of images/objects with a box counts");
	auto *json = cmd->add_option("--json", opt->json, "write the full report (and PR curves at z=0.10) as JSON");
	auto *plot = cmd->add_option("--plot", opt->plot, "draw precision-recall curves to this PNG");
	auto *vsd = cmd->add_flag(
		"--vsd", opt->visibleSurface,
		"also score the visible surface (BOP's VSD, average recall AR_VSD): the surface the "
		"depth shows, not the hidden parts; reads the split's depth images");
	for (CLI::Option *resultsOnly : {objects, targets, json, plot, vsd})
		resultsOnly->excludes(runPoses);
	cmd->callback([&action, opt, results, runPoses] {
		if (!*results && !*runPoses)
			throw CLI::RequiredError("--results or --run-poses");
		const bool poses = runPoses->count() > 0;
		action = [opt, poses] { return poses ? runEvalRunPoses(*opt) : runEval(*opt); };
	});
}

} // namespace ihf::app
