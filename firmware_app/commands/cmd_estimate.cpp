// SPDX-License-Identifier: MIT
// `ihf estimate`: runs the IHF on every given box of a BOP dataset and
// writes a BOP results CSV.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "core/dataset/atomic_file.h"
#include "core/tracking/stream_estimator.h"
#include "drivers/clock.h"
#include "firmware_app/commands/command.h"
#include "firmware_app/commands/estimate_stats.h"
#include "firmware_app/commands/estimate_trace.h"
#include "firmware_app/config/pipeline_config.h"
#include "firmware_app/runtime/forest_set.h"
#include "firmware_app/runtime/frame_estimator.h"
#include "firmware_app/runtime/pose_pipeline.h"

namespace ihf::app {

namespace {

struct EstimateOptions {
	std::string dataset;
	std::string split;
	std::string boxes;
	std::vector<std::string> forests;
	std::string out;
	std::string config;
	std::string statsJson;
	std::string boxKind; // empty: the config's
	int iterations = -1;
	double budgetMs = -1;
	int threads = -1;
	bool noIcp = false;
	bool noViews = false;
	bool noHalfTurns = false;
	bool paper = false;
	bool quiet = false;
	bool noTime = false;
	std::string trace;
	bool sequence = false;  // --sequence: each scene a stream, tracked
	std::string runConfig;  // --run-config: [tracking] from a device configuration
};

// A box's pose as a row of the results CSV: its score is the confidence.
ResultRow resultRow(int sceneId, int imId, int objId, const PoseEstimate &e)
{
	ResultRow r;
	r.sceneId = sceneId;
	r.imId = imId;
	r.objId = objId;
	r.score = e.confidence;
	r.pose = e.pose;
	return r;
}

// Each box's answer into the CSV rows and the run's counts and times.
class EstimateTally : public BoxSink
{
public:
	EstimateTally(bool tracking, bool quiet) : tracking_(tracking), quiet_(quiet) {}

	// The image whose boxes follow.
	void beginImage(int sceneId, int imId)
	{
		sceneId_ = sceneId, imId_ = imId;
		imageRows_.clear();
		imageTime = 0;
	}
	// Its rows into rows, each with the image's time (-1 without it).
	void endImage(bool noTime)
	{
		for (ResultRow &r : imageRows_) {
			r.time = noTime ? -1 : imageTime;
			rows.push_back(r);
		}
	}

	Status onBox(const FrameBox &box, const ObjectModel *model, const StreamResult &r) override
	{
		if (!model) {
			if (!quiet_)
				std::fprintf(stderr, "ihf estimate: scene %d image %d: no forest for object %d; box skipped\n",
					     sceneId_, imId_, box.objId);
			++skipped;
			return {};
		}
		++modes[r.mode];
		if (r.mode == BoxMode::kTrack || r.mode == BoxMode::kDetect) {
			boxTimes.push_back(r.ns * 1e-9);
			if (tracking_)
				(r.mode == BoxMode::kTrack ? trackTimes : detectTimes).push_back(r.ns * 1e-9);
			imageTime += r.ns * 1e-9;
			++done;
		}
		if (!quiet_) {
			// A box without a pose, or answered unconfirmed (provisional).
			if (tracking_ && (!r.estimate.found || r.provisional))
				std::fprintf(stderr, "ihf estimate: scene %d image %d object %d: %s: %s\n", sceneId_, imId_,
					     box.objId, boxModeName(r.mode), r.estimate.reason);
			else if (!tracking_ && !r.estimate.found)
				std::fprintf(stderr, "ihf estimate: scene %d image %d object %d: no pose: %s\n", sceneId_,
					     imId_, box.objId, r.estimate.reason);
		}
		if (!r.estimate.found) {
			++noPose;
			return {};
		}
		imageRows_.push_back(resultRow(sceneId_, imId_, box.objId, r.estimate));
		if (r.estimate.ambiguous)
			ambiguous.push_back({sceneId_, imId_, box.objId, r.estimate.ambiguityAxis});
		return {};
	}

	std::vector<ResultRow> rows;
	std::vector<AmbiguousPose> ambiguous;
	std::vector<double> boxTimes, trackTimes, detectTimes;
	double imageTime = 0;
	int skipped = 0, noPose = 0, done = 0;
	std::map<BoxMode, int> modes;

private:
	bool tracking_, quiet_;
	int sceneId_ = 0, imId_ = 0;
	std::vector<ResultRow> imageRows_;
};

// The settings of the run: the configuration with the options' overrides.
Expected<EstimateSettings> estimateSettings(const EstimateOptions &o)
{
	auto settings = loadEstimateConfig(o.config);
	if (!settings)
		return settings.error();
	EstimateSettings &s = *settings;
	if (o.iterations >= 0)
		s.estimator.iterations = o.iterations;
	if (o.paper)
		applyPapersMethod(s.estimator);
	if (o.noIcp)
		s.estimator.icp = false;
	if (o.noViews)
		s.estimator.views.inplane = 0;
	if (o.noHalfTurns)
		s.estimator.halfTurns.candidates = 0;
	if (o.budgetMs >= 0)
		s.estimator.frameBudgetMs = static_cast<float>(o.budgetMs);
	if (o.threads >= 0)
		s.limits.threads = o.threads;
	return settings;
}

// The tracking summary of a --sequence run, on stderr.
void printTracking(const TrackingStats &t, const EstimateTally &tally, const std::vector<double> &frameTimes)
{
	auto mode = [&](BoxMode m) {
		const auto it = tally.modes.find(m);
		return it == tally.modes.end() ? 0 : it->second;
	};
	std::fprintf(stderr,
		     "ihf estimate: tracking: %d tracked, %d detected (%llu re-detected), %d deferred (%llu provisional), "
		     "%d duplicate; "
		     "tracks started %llu, lost %llu; tracked box median %.2f ms p99 %.2f ms; detected box median "
		     "%.1f ms p99 %.1f ms; frame overruns %llu, worst frame %.1f ms\n",
		     mode(BoxMode::kTrack), mode(BoxMode::kDetect), static_cast<unsigned long long>(t.redetected),
		     mode(BoxMode::kDeferred), static_cast<unsigned long long>(t.provisional), mode(BoxMode::kDuplicate),
		     static_cast<unsigned long long>(t.started), static_cast<unsigned long long>(t.lost),
		     1e3 * percentile(tally.trackTimes, 0.5), 1e3 * percentile(tally.trackTimes, 0.99),
		     1e3 * percentile(tally.detectTimes, 0.5), 1e3 * percentile(tally.detectTimes, 0.99),
		     static_cast<unsigned long long>(t.frameOverruns), t.worstFrameNs * 1e-6);
	std::fprintf(stderr,
		     "ihf estimate: tracking: frames with boxes %zu, frame median %.1f ms p99 %.1f ms; "
		     "refreshed %llu (%llu won, %llu ambiguous told apart), forced %llu, longest wait %d frames\n",
		     frameTimes.size(), 1e3 * percentile(frameTimes, 0.5), 1e3 * percentile(frameTimes, 0.99),
		     static_cast<unsigned long long>(t.refreshed), static_cast<unsigned long long>(t.refreshWins),
		     static_cast<unsigned long long>(t.refreshSettled),
		     static_cast<unsigned long long>(t.forced), t.maxWait);
	std::fprintf(stderr, "ihf estimate: tracked poses not kept:");
	for (size_t v = 1; v < t.rejected.size(); ++v)
		if (t.rejected[v])
			std::fprintf(stderr, " %s %llu;", trackVerdictName(static_cast<TrackVerdict>(v)),
				     static_cast<unsigned long long>(t.rejected[v]));
	std::fprintf(stderr, "\n");
}

int runEstimate(const EstimateOptions &o)
{
	auto settings = estimateSettings(o);
	if (!settings) {
		std::fprintf(stderr, "ihf estimate: %s\n", settings.error().message.c_str());
		return kExitFailure;
	}
	EstimateSettings &s = *settings;
	if (!o.boxKind.empty()) {
		Expected<BoxKind> kind = parseBoxKind(o.boxKind, "--box-kind");
		if (!kind) {
			std::fprintf(stderr, "ihf estimate: %s\n", kind.error().message.c_str());
			return kExitUsage;
		}
		useBoxKind(s, *kind);
	}

	Expected<std::map<int, std::filesystem::path>> forestFiles = parseForestOptions(o.forests);
	if (!forestFiles) {
		std::fprintf(stderr, "ihf estimate: %s\n", forestFiles.error().message.c_str());
		return kExitUsage;
	}
	TrackerConfig tracking;
	if (!o.runConfig.empty()) {
		Expected<RunSettings> run = loadRunConfig(o.runConfig);
		if (!run) {
			std::fprintf(stderr, "ihf estimate: %s\n", run.error().message.c_str());
			return kExitFailure;
		}
		tracking = run->tracking;
	}
	// The forests, the estimator and (--sequence) the tracker, as ihf run
	// builds them; the frames go through the same per-frame path.
	SteadyPacingClock clock;
	Expected<std::unique_ptr<PosePipeline>> pipeline =
		PosePipeline::create(*forestFiles, s, o.sequence ? &tracking : nullptr, clock, "ihf estimate");
	if (!pipeline) {
		std::fprintf(stderr, "ihf estimate: %s\n", pipeline.error().message.c_str());
		return kExitFailure;
	}
	PosePipeline &poses = **pipeline;
	FrameEstimator &frames = poses.frames();

	auto dataset = BopDataset::open(o.dataset, o.split);
	if (!dataset) {
		std::fprintf(stderr, "ihf estimate: %s\n", dataset.error().message.c_str());
		return kExitFailure;
	}
	auto dets = readDetections(o.boxes);
	if (!dets) {
		std::fprintf(stderr, "ihf estimate: %s\n", dets.error().message.c_str());
		return kExitFailure;
	}

	// Boxes grouped per image, images in scene and id order.
	std::map<std::pair<int, int>, std::vector<const Detection *>> perImage;
	for (const auto &d : *dets)
		perImage[{d.sceneId, d.imageId}].push_back(&d);

	std::unique_ptr<std::FILE, int (*)(std::FILE *)> traceFile(nullptr, &std::fclose);
	std::unique_ptr<EstimateTrace> trace;
	if (!o.trace.empty()) {
		traceFile.reset(std::fopen(o.trace.c_str(), "w"));
		if (!traceFile) {
			std::fprintf(stderr, "ihf estimate: cannot write the trace %s\n", o.trace.c_str());
			return kExitFailure;
		}
		trace = std::make_unique<EstimateTrace>(traceFile.get(), poses.estimator(), frames.config());
		poses.estimator().setObserver(trace.get());
		frames.setBoxObserver(trace.get());
	}
	std::map<int, BopScene> scenes;
	// Per scene, with --trace: why it has no ground truth ("" if it has).
	std::map<int, std::string> noTruth;
	// A stream's frames are all of its scene's images, in id order: a
	// frame without boxes still ages the tracks.
	if (o.sequence) {
		std::map<std::pair<int, int>, std::vector<const Detection *>> streamFrames;
		std::set<int> listed;
		for (const auto &[key, boxes] : perImage) {
			const int sceneId = key.first;
			if (listed.insert(sceneId).second) {
				auto scene = dataset->loadSceneCameras(sceneId);
				if (!scene) {
					std::fprintf(stderr, "ihf estimate: %s\n", scene.error().message.c_str());
					return kExitFailure;
				}
				for (const auto &[imId, camera] : scene->cameras)
					streamFrames[{sceneId, imId}];
			}
			streamFrames[key] = boxes;
		}
		perImage = std::move(streamFrames);
	}
	EstimateTally tally(o.sequence, o.quiet);
	std::vector<double> frameTimes; // --sequence: frames with boxes
	std::vector<FrameBox> frameBoxes;
	bool warmedUp = false;
	int streamScene = -1;
	for (const auto &[key, boxes] : perImage) {
		auto [sceneId, imId] = key;
		if (!scenes.count(sceneId)) {
			// Estimation needs the cameras only; the ground truth is read
			// for the trace, and a scene without it is traced without.
			auto scene = dataset->loadSceneCameras(sceneId);
			if (!scene) {
				std::fprintf(stderr, "ihf estimate: %s\n", scene.error().message.c_str());
				return kExitFailure;
			}
			if (trace) {
				if (Status gt = dataset->loadSceneGt(*scene); !gt) {
					noTruth[sceneId] = gt.error().message;
					std::fprintf(stderr, "ihf estimate: scene %d has no ground truth to trace against: %s\n",
						     sceneId, gt.error().message.c_str());
				}
			}
			scenes[sceneId] = std::move(scene.value());
		}
		const BopScene &scene = scenes[sceneId];
		auto camIt = scene.cameras.find(imId);
		if (camIt == scene.cameras.end()) {
			std::fprintf(stderr, "ihf estimate: scene %d image %d: not in scene_camera.json; boxes skipped\n",
				     sceneId, imId);
			tally.skipped += static_cast<int>(boxes.size());
			continue;
		}
		if (o.sequence && sceneId != streamScene) {
			frames.beginStream();
			streamScene = sceneId;
		}
		if (o.sequence && boxes.empty()) {
			// Nothing to estimate: the tracks only age.
			frames.skipFrame(static_cast<uint64_t>(imId), camIt->second.intrinsics);
			continue;
		}
		auto depth = dataset->loadDepthMm(sceneId, imId, camIt->second.depthScale);
		if (!depth) {
			// A bad frame is skipped and counted; the run goes on.
			std::fprintf(stderr, "ihf estimate: %s; frame skipped\n", depth.error().message.c_str());
			tally.skipped += static_cast<int>(boxes.size());
			continue;
		}
		CameraIntrinsics K = camIt->second.intrinsics;
		K.width = depth->width();
		K.height = depth->height();
		// Before the first frame, not timed.
		if (!warmedUp) {
			warmedUp = true;
			frames.warmUp(K, "ihf estimate");
		}

		frameBoxes.clear();
		bool anyForest = false;
		for (const Detection *d : boxes) {
			frameBoxes.push_back(FrameBox{d->categoryId, d->bbox, 0});
			anyForest = anyForest || frames.model(d->categoryId);
		}
		if (trace)
			trace->setImage(sceneId, scene, noTruth.count(sceneId) ? noTruth[sceneId] : std::string());
		tally.beginImage(sceneId, imId);
		const auto f0 = std::chrono::steady_clock::now();
		if (Status st = frames.estimate(static_cast<uint64_t>(imId), depth->view(), K, frameBoxes, tally); !st) {
			std::fprintf(stderr, "ihf estimate: %s\n", st.error().message.c_str());
			return kExitFailure;
		}
		if (o.sequence && anyForest)
			frameTimes.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count());
		tally.endImage(o.noTime);
	}
	if (auto st = writeResultsCsv(o.out, tally.rows); !st) {
		std::fprintf(stderr, "ihf estimate: %s\n", st.error().message.c_str());
		return kExitFailure;
	}
	EstimateRunSummary summary{poses.estimator().stats(), s.limits, s.estimator.frameBudgetMs, tally.boxTimes,
				   boxKindName(s.boxKind), s.estimator.score, tally.ambiguous};
	// Both files before the report: stderr read by a pipe that closes
	// early (`| head`) ends the process at its next write.
	if (!o.statsJson.empty()) {
		if (auto st = writeFileAtomic(o.statsJson, estimateStatsJson(summary)); !st) {
			std::fprintf(stderr, "ihf estimate: %s\n", st.error().message.c_str());
			return kExitFailure;
		}
	}
	std::fprintf(stderr,
		     "ihf estimate: %d boxes, %zu poses, %d no pose, %d skipped; per box median %.1f ms, "
		     "p99 %.1f ms; wrote %s\n",
		     tally.done, tally.rows.size(), tally.noPose, tally.skipped, 1e3 * percentile(tally.boxTimes, 0.5),
		     1e3 * percentile(tally.boxTimes, 0.99), o.out.c_str());
	if (const StreamEstimator *tracker = poses.tracker())
		printTracking(tracker->stats(), tally, frameTimes);
	if (!tally.ambiguous.empty())
		std::fprintf(stderr, "ihf estimate: %zu poses ambiguous (a turn the depth cannot tell apart; --stats-json lists them)\n",
			     tally.ambiguous.size());
	printEstimateStats(stderr, summary);
	return kExitOk;
}

} // namespace

void addEstimateCommand(CLI::App &root, Action &action)
{
	auto opts = std::make_shared<EstimateOptions>();
	auto *cmd = root.add_subcommand("estimate", "Estimate 6D poses in the given boxes of a BOP dataset");
	cmd->add_option("--dataset", opts->dataset, "BOP dataset folder")->required()->check(CLI::ExistingDirectory);
	cmd->add_option("--split", opts->split, "Split folder (default: test, val or train)");
	cmd->add_option("--boxes", opts->boxes, "Given boxes (BOP detection JSON list)")->required()->check(CLI::ExistingFile);
	cmd->add_option("--forest", opts->forests, "OBJ_ID=FILE.ihf, one per object")->required();
	cmd->add_option("--out", opts->out, "Results CSV to write (BOP format)")->required();
	cmd->add_option("--config", opts->config, "Estimation configuration (TOML), e.g. config/estimate.toml")
		->check(CLI::ExistingFile);
	cmd->add_option("--iterations", opts->iterations, "Refinement iterations k (0: initial registration only)")
		->check(CLI::Range(0, 100));
	cmd->add_option("--box-kind", opts->boxKind,
			"What the boxes bound: amodal (the whole object, as BOP's bbox_obj) or modal (its visible "
			"part, as most detectors give); selects the score's weights (default from the config, amodal)")
		->check(CLI::IsMember({"amodal", "modal"}));
	cmd->add_flag("--no-icp", opts->noIcp, "Skip the final ICP polish");
	cmd->add_flag("--no-views", opts->noViews, "Skip the view-template rotation search");
	cmd->add_flag("--no-half-turns", opts->noHalfTurns, "Skip the half-turns of the best hypotheses");
	cmd->add_flag("--paper", opts->paper,
		      "The paper's method alone: --no-icp --no-views --no-half-turns, refinement iterations voting as the registration");
	cmd->add_option("--budget-ms", opts->budgetMs,
			"Estimation time per frame in ms, shared by its boxes (overrides [budget] estimation_budget_ms; "
			"0: unlimited)")
		->check(CLI::Range(0.0, 1e6));
	cmd->add_option("--threads", opts->threads,
			"Threads of a box's view search, the caller included (0: one per core; default from the config)")
		->check(CLI::Range(0, WorkerPool::kMaxThreads));
	cmd->add_option("--stats-json", opts->statsJson,
			"Also write the per-stage times, budget counters and arena use as JSON");
	cmd->add_flag("--quiet", opts->quiet, "Do not report per-box failures");
	cmd->add_flag("--no-time", opts->noTime,
		      "Write -1 (unknown, as BOP allows) in the CSV's time column, so that two runs' files can be "
		      "compared byte for byte");
	cmd->add_option("--trace", opts->trace,
			"Write every scored hypothesis (and the ground truth's score, if the dataset has scene_gt.json) "
			"and, for a nearly symmetric object, every comparison of the best with a rival turn as JSON "
			"lines");
	cmd->add_flag("--sequence", opts->sequence,
		      "Each scene is a stream (images in id order): boxes are tracked from frame to frame and "
		      "detected only where needed, as ihf run does");
	cmd->add_option("--run-config", opts->runConfig,
			"With --sequence: the [tracking] settings of this device configuration (default: as shipped)")
		->check(CLI::ExistingFile);
	cmd->callback([opts, &action] { action = [opts] { return runEstimate(*opts); }; });
}

} // namespace ihf::app
