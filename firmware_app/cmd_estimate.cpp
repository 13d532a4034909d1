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
#include "core/estimation/pose_estimator.h"
#include "core/tracking/stream_estimator.h"
#include "core/dataset/atomic_file.h"
#include "core/model/forest_file.h"
#include "firmware_app/command.h"
#include "firmware_app/forest_set.h"
#include "firmware_app/estimate_stats.h"
#include "firmware_app/pipeline_config.h"
#include "firmware_app/warm_up_note.h"

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

// `--trace`: every scored hypothesis as a JSON line, for diagnosing which
// stage loses a pose. Ground-truth poses of the box's object, when the
// dataset has them, are scored the same way (stage "given"); when it has
// none, a line of stage "no_truth" says why; the box's answer comes last
// (stage "result").
class TraceWriter : public EstimateObserver
{
public:
	explicit TraceWriter(std::FILE *f) : f_(f) {}
	void begin(int scene, int image, int obj, double diameter)
	{
		scene_ = scene, image_ = image, obj_ = obj, diameter_ = diameter;
		truth_.clear();
	}
	void addTruth(const Pose &pose) { truth_.push_back(pose); }
	// No ground truth to compare this box with: no "given" lines and no vote
	// shares follow.
	void noTruth(const std::string &why)
	{
		std::fprintf(f_, "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"stage\":\"no_truth\",\"reason\":",
			     scene_, image_, obj_);
		writeString(why);
		std::fprintf(f_, "}\n");
	}
	// Share of the vote weight near a ground-truth pose: rotation within
	// 20 deg, centre within 0.1 diameter, and both.
	void onVotes(const VoteEvent &e) override
	{
		for (size_t g = 0; g < truth_.size(); ++g) {
			const Eigen::Matrix3f Rg = (e.cropRotation.transpose() * truth_[g].R).cast<float>();
			const Eigen::Vector3f tg = (e.cropRotation.transpose() * truth_[g].t).cast<float>();
			const Eigen::Quaternionf qg(Rg);
			const float cosHalf = std::cos(0.5f * 20.0f * static_cast<float>(M_PI) / 180.0f);
			const float near = static_cast<float>(0.1 * diameter_);
			double all = 0, rot = 0, trans = 0, both = 0;
			for (const CastVote &v : e.votes) {
				const bool r = std::abs(v.rotation.dot(qg)) > cosHalf;
				const bool t = (v.centre - tg).norm() < near;
				all += v.weight;
				rot += r ? v.weight : 0;
				trans += t ? v.weight : 0;
				both += r && t ? v.weight : 0;
			}
			std::fprintf(f_,
				     "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"iteration\":%d,\"stage\":\"votes\","
				     "\"pass\":%d,\"truth\":%zu,\"votes\":%zu,\"rot\":%.4f,\"trans\":%.4f,\"both\":%.4f}\n",
				     scene_, image_, obj_, e.iteration, e.pass, g, e.votes.size(),
				     all > 0 ? rot / all : 0, all > 0 ? trans / all : 0, all > 0 ? both / all : 0);
		}
	}
	void onHypothesis(const HypothesisEvent &e) override
	{
		std::fprintf(f_, "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"iteration\":%d,\"stage\":\"%s\",\"rank\":%d,",
			     scene_, image_, obj_, e.iteration, e.stage, e.rank);
		writePose(e.pose);
		std::fprintf(f_,
			     ",\"score\":%.4f,\"depth_score\":%.4f,\"box\":%.4f,\"inliers\":%d,\"outliers\":%d,"
			     "\"occluded\":%d,\"rendered\":%d,\"density\":%.4f}\n",
			     e.score.score, e.score.depthScore, e.score.boxFactor, e.score.inliers, e.score.outliers,
			     e.score.occluded, e.score.rendered, e.voteDensity);
	}

	// The box's answer, after its hypotheses: the winner's pose and score,
	// and the confidence and margin the CSV's score comes from.
	void onResult(const PoseEstimate &e)
	{
		std::fprintf(f_,
			     "{\"scene_id\":%d,\"im_id\":%d,\"obj_id\":%d,\"stage\":\"result\",\"found\":%s,"
			     "\"reason\":\"%s\",",
			     scene_, image_, obj_, e.found ? "true" : "false", e.reason);
		writePose(e.pose);
		std::fprintf(f_, ",\"score\":%.4f,\"confidence\":%.4f,\"margin\":%.4f,\"iterations\":%d,\"best_iteration\":%d,"
			     "\"ambiguous\":%s}\n",
			     e.score.score, e.confidence, e.margin, e.iterationsDone, e.bestIteration,
			     e.ambiguous ? "true" : "false");
	}

private:
	// A JSON string (reasons hold file paths).
	void writeString(const std::string &text)
	{
		std::fputc('"', f_);
		for (unsigned char c : text) {
			if (c == '"' || c == '\\')
				std::fprintf(f_, "\\%c", c);
			else if (c < 0x20)
				std::fprintf(f_, "\\u%04x", c);
			else
				std::fputc(c, f_);
		}
		std::fputc('"', f_);
	}

	// "R":[9 numbers],"t":[3 numbers] of a trace line.
	void writePose(const Pose &p)
	{
		const Eigen::Matrix3d &R = p.R;
		std::fprintf(f_, "\"R\":[%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f],\"t\":[%.3f,%.3f,%.3f]", R(0, 0),
			     R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2), p.t.x(), p.t.y(),
			     p.t.z());
	}

	std::FILE *f_;
	int scene_ = 0, image_ = 0, obj_ = 0;
	double diameter_ = 0;
	std::vector<Pose> truth_;
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

int runEstimate(const EstimateOptions &o)
{
	auto settings = loadEstimateConfig(o.config);
	if (!settings) {
		std::fprintf(stderr, "ihf estimate: %s\n", settings.error().message.c_str());
		return kExitFailure;
	}
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
	Expected<ForestSet> forests = ForestSet::load(*forestFiles, s, "ihf estimate");
	if (!forests) {
		std::fprintf(stderr, "ihf estimate: %s\n", forests.error().message.c_str());
		return kExitFailure;
	}
	const std::map<int, const ObjectModel *> &models = forests->models();

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
	TrackerConfig tracking;
	if (!o.runConfig.empty()) {
		Expected<RunSettings> run = loadRunConfig(o.runConfig);
		if (!run) {
			std::fprintf(stderr, "ihf estimate: %s\n", run.error().message.c_str());
			return kExitFailure;
		}
		tracking = run->tracking;
	}

	PoseEstimator estimator(s.limits);
	if (!estimator.valid()) {
		std::fprintf(stderr, "ihf estimate: cannot allocate the estimator's arena of %zu bytes\n",
			     PoseEstimator::arenaBytes(s.limits));
		return kExitFailure;
	}
	std::unique_ptr<std::FILE, int (*)(std::FILE *)> traceFile(nullptr, &std::fclose);
	std::unique_ptr<TraceWriter> trace;
	if (!o.trace.empty()) {
		traceFile.reset(std::fopen(o.trace.c_str(), "w"));
		if (!traceFile) {
			std::fprintf(stderr, "ihf estimate: cannot write the trace %s\n", o.trace.c_str());
			return kExitFailure;
		}
		trace = std::make_unique<TraceWriter>(traceFile.get());
		estimator.setObserver(trace.get());
	}
	std::unique_ptr<StreamEstimator> tracker;
	if (o.sequence) {
		tracker = std::make_unique<StreamEstimator>(estimator, tracking);
		if (!tracker->valid()) {
			std::fprintf(stderr, "ihf estimate: cannot allocate the tracker's arena\n");
			return kExitFailure;
		}
	}
	std::map<int, BopScene> scenes;
	// Per scene, with --trace: why it has no ground truth ("" if it has).
	std::map<int, std::string> noTruth;
	// A stream's frames are all of its scene's images, in id order: a
	// frame without boxes still ages the tracks.
	if (tracker) {
		std::map<std::pair<int, int>, std::vector<const Detection *>> frames;
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
					frames[{sceneId, imId}];
			}
			frames[key] = boxes;
		}
		perImage = std::move(frames);
	}
	std::vector<ResultRow> rows;
	std::vector<double> boxTimes;
	std::vector<AmbiguousPose> ambiguous;
	int skipped = 0, noPose = 0, done = 0;
	bool warmedUp = false;
	int streamScene = -1;
	std::map<BoxMode, int> modes;
	std::vector<double> trackTimes, detectTimes, frameTimes;
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
			skipped += static_cast<int>(boxes.size());
			continue;
		}
		if (tracker && boxes.empty()) {
			// Nothing to estimate: the tracks only age.
			if (sceneId != streamScene) {
				tracker->reset();
				streamScene = sceneId;
			}
			tracker->estimateFrame(static_cast<uint64_t>(imId), {}, camIt->second.intrinsics, {}, s.estimator,
					       s.estimator.frameBudgetMs, {});
			continue;
		}
		auto depth = dataset->loadDepthMm(sceneId, imId, camIt->second.depthScale);
		if (!depth) {
			// A bad frame is skipped and counted; the run goes on.
			std::fprintf(stderr, "ihf estimate: %s; frame skipped\n", depth.error().message.c_str());
			skipped += static_cast<int>(boxes.size());
			continue;
		}
		CameraIntrinsics K = camIt->second.intrinsics;
		K.width = depth->width();
		K.height = depth->height();

		// Under a budget the first frame's stages must be predicted from a
		// measurement, not taken as free: one synthetic box per object,
		// before the first frame (not timed).
		if (s.estimator.frameBudgetMs > 0 && !warmedUp) {
			warmedUp = true;
			for (const auto &[id, model] : models)
				if (const std::string note = warmUpNote(id, estimator.warmUp(*model, K, s.estimator),
									     s.estimator.frameBudgetMs);
				    !note.empty())
					std::fprintf(stderr, "ihf estimate: %s\n", note.c_str());
		}

		if (tracker) {
			if (sceneId != streamScene) {
				tracker->reset();
				streamScene = sceneId;
			}
			std::vector<StreamBox> streamBoxes;
			std::vector<const Detection *> streamDets;
			for (const Detection *d : boxes) {
				auto mIt = models.find(d->categoryId);
				if (mIt == models.end()) {
					if (!o.quiet)
						std::fprintf(stderr,
							     "ihf estimate: scene %d image %d: no forest for object %d; box skipped\n",
							     sceneId, imId, d->categoryId);
					skipped++;
					continue;
				}
				streamBoxes.push_back({d->categoryId, pixelsOfBox(d->bbox), 0, mIt->second});
				streamDets.push_back(d);
			}
			std::vector<StreamResult> results(streamBoxes.size());
			const auto f0 = std::chrono::steady_clock::now();
			tracker->estimateFrame(static_cast<uint64_t>(imId), depth->view(), K, streamBoxes, s.estimator,
					       s.estimator.frameBudgetMs, results);
			if (!streamBoxes.empty())
				frameTimes.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count());
			std::vector<ResultRow> imageRows;
			double imageTime = 0;
			for (size_t i = 0; i < results.size(); ++i) {
				const StreamResult &r = results[i];
				const Detection *d = streamDets[i];
				++modes[r.mode];
				if (r.mode == BoxMode::kTrack || r.mode == BoxMode::kDetect) {
					boxTimes.push_back(r.ns * 1e-9);
					(r.mode == BoxMode::kTrack ? trackTimes : detectTimes).push_back(r.ns * 1e-9);
					imageTime += r.ns * 1e-9;
					++done;
				}
				// A box without a pose, or answered unconfirmed (provisional).
				if ((!r.estimate.found || r.provisional) && !o.quiet)
					std::fprintf(stderr, "ihf estimate: scene %d image %d object %d: %s: %s\n", sceneId,
						     imId, d->categoryId, boxModeName(r.mode), r.estimate.reason);
				if (!r.estimate.found) {
					++noPose;
					continue;
				}
				imageRows.push_back(resultRow(sceneId, imId, d->categoryId, r.estimate));
				if (r.estimate.ambiguous)
					ambiguous.push_back({sceneId, imId, d->categoryId, r.estimate.ambiguityAxis});
			}
			for (auto &r : imageRows) {
				r.time = o.noTime ? -1 : imageTime;
				rows.push_back(r);
			}
			continue;
		}

		std::vector<ResultRow> imageRows;
		double imageTime = 0;
		// The frame's budget is shared by the boxes that have a forest.
		const int frameBoxes = static_cast<int>(std::count_if(boxes.begin(), boxes.end(), [&](const Detection *d) {
			return models.count(d->categoryId) > 0;
		}));
		estimator.beginFrame(frameBoxes, s.estimator.frameBudgetMs);
		for (const Detection *d : boxes) {
			auto mIt = models.find(d->categoryId);
			if (mIt == models.end()) {
				if (!o.quiet)
					std::fprintf(stderr, "ihf estimate: scene %d image %d: no forest for object %d; box skipped\n",
						     sceneId, imId, d->categoryId);
				skipped++;
				continue;
			}
			const PixelBox box = pixelsOfBox(d->bbox);
			if (trace) {
				trace->begin(sceneId, imId, d->categoryId, mIt->second->params().diameter);
				auto gtIt = scene.gt.find(imId);
				const bool known = gtIt != scene.gt.end() &&
						   std::any_of(gtIt->second.begin(), gtIt->second.end(),
							       [&](const GtInstance &g) { return g.objId == d->categoryId; });
				if (auto why = noTruth.find(sceneId); why != noTruth.end())
					trace->noTruth(why->second);
				else if (!known)
					trace->noTruth("scene_gt.json has no object " + std::to_string(d->categoryId) +
						       " in image " + std::to_string(imId));
				if (known)
					for (const GtInstance &g : gtIt->second) {
						if (g.objId != d->categoryId)
							continue;
						trace->addTruth(g.pose);
						auto gs = estimator.scorePose(depth->view(), K, box, *mIt->second,
									      s.estimator, g.pose);
						if (gs) {
							HypothesisEvent ev;
							ev.stage = "given";
							ev.pose = g.pose;
							ev.score = *gs;
							trace->onHypothesis(ev);
						}
					}
			}
			auto t0 = std::chrono::steady_clock::now();
			PoseEstimate e = estimator.estimate(depth->view(), K, box, *mIt->second, s.estimator);
			double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
			boxTimes.push_back(dt);
			imageTime += dt;
			++done;
			if (trace)
				trace->onResult(e);
			if (!e.found) {
				++noPose;
				if (!o.quiet)
					std::fprintf(stderr, "ihf estimate: scene %d image %d object %d: no pose: %s\n",
						     sceneId, imId, d->categoryId, e.reason);
				continue;
			}
			imageRows.push_back(resultRow(sceneId, imId, d->categoryId, e));
			if (e.ambiguous)
				ambiguous.push_back({sceneId, imId, d->categoryId, e.ambiguityAxis});
		}
		estimator.endFrame();
		for (auto &r : imageRows) {
			r.time = o.noTime ? -1 : imageTime;
			rows.push_back(r);
		}
	}
	if (auto st = writeResultsCsv(o.out, rows); !st) {
		std::fprintf(stderr, "ihf estimate: %s\n", st.error().message.c_str());
		return kExitFailure;
	}
	std::fprintf(stderr,
		     "ihf estimate: %d boxes, %zu poses, %d no pose, %d skipped; per box median %.1f ms, "
		     "p99 %.1f ms; wrote %s\n",
		     done, rows.size(), noPose, skipped, 1e3 * percentile(boxTimes, 0.5),
		     1e3 * percentile(boxTimes, 0.99), o.out.c_str());
	if (tracker) {
		const TrackingStats &t = tracker->stats();
		std::fprintf(stderr,
			     "ihf estimate: tracking: %d tracked, %d detected (%llu re-detected), %d deferred (%llu provisional), "
			     "%d duplicate; "
			     "tracks started %llu, lost %llu; tracked box median %.2f ms p99 %.2f ms; detected box median "
			     "%.1f ms p99 %.1f ms; frame overruns %llu, worst frame %.1f ms\n",
			     modes[BoxMode::kTrack], modes[BoxMode::kDetect], static_cast<unsigned long long>(t.redetected),
			     modes[BoxMode::kDeferred], static_cast<unsigned long long>(t.provisional), modes[BoxMode::kDuplicate], static_cast<unsigned long long>(t.started),
			     static_cast<unsigned long long>(t.lost), 1e3 * percentile(trackTimes, 0.5),
			     1e3 * percentile(trackTimes, 0.99), 1e3 * percentile(detectTimes, 0.5),
			     1e3 * percentile(detectTimes, 0.99), static_cast<unsigned long long>(t.frameOverruns),
			     t.worstFrameNs * 1e-6);
		std::fprintf(stderr,
			     "ihf estimate: tracking: frames with boxes %zu, frame median %.1f ms p99 %.1f ms; "
			     "refreshed %llu (%llu won), forced %llu, longest wait %d frames\n",
			     frameTimes.size(), 1e3 * percentile(frameTimes, 0.5), 1e3 * percentile(frameTimes, 0.99),
			     static_cast<unsigned long long>(t.refreshed), static_cast<unsigned long long>(t.refreshWins),
			     static_cast<unsigned long long>(t.forced), t.maxWait);
		std::fprintf(stderr, "ihf estimate: tracked poses not kept:");
		for (size_t v = 1; v < t.rejected.size(); ++v)
			if (t.rejected[v])
				std::fprintf(stderr, " %s %llu;", trackVerdictName(static_cast<TrackVerdict>(v)),
					     static_cast<unsigned long long>(t.rejected[v]));
		std::fprintf(stderr, "\n");
	}
	EstimateRunSummary summary{estimator.stats(), s.limits, s.estimator.frameBudgetMs, boxTimes,
				   boxKindName(s.boxKind), s.estimator.score, ambiguous};
	if (!ambiguous.empty())
		std::fprintf(stderr, "ihf estimate: %zu poses ambiguous (a turn the depth cannot tell apart; --stats-json lists them)\n",
			     ambiguous.size());
	printEstimateStats(stderr, summary);
	if (!o.statsJson.empty()) {
		if (auto st = writeFileAtomic(o.statsJson, estimateStatsJson(summary)); !st) {
			std::fprintf(stderr, "ihf estimate: %s\n", st.error().message.c_str());
			return kExitFailure;
		}
	}
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
			"as JSON lines");
	cmd->add_flag("--sequence", opts->sequence,
		      "Each scene is a stream (images in id order): boxes are tracked from frame to frame and "
		      "detected only where needed, as ihf run does");
	cmd->add_option("--run-config", opts->runConfig,
			"With --sequence: the [tracking] settings of this device configuration (default: as shipped)")
		->check(CLI::ExistingFile);
	cmd->callback([opts, &action] { action = [opts] { return runEstimate(*opts); }; });
}

} // namespace ihf::app
