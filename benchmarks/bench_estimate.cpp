// SPDX-License-Identifier: MIT
// Per-box latency of PoseEstimator::estimate on the real LM-O frame
// (test/000002 image 3): the object's bbox_obj enlarged by 10%, shifted by a
// few pixels from box to box. The configuration is `ihf estimate`'s default
// (config/estimate.toml, the model prepared as ihf prepares it: view
// templates and the simplified render mesh). Arguments: k (refinement
// iterations), ICP on or off (off also turns the half-turns off, as
// `ihf estimate --no-icp`), frame budget in ms (0: unlimited; one box per
// frame).
//
// The model: IHF_BENCH_FOREST=F.ihf (a forest file from `ihf train`) if set,
// else a small forest trained at start-up from the LM-O mesh of object
// IHF_BENCH_OBJ (default 9, the duck: 96% visible in the frame). The small
// forest is shallower than one trained with config/train.toml, so its
// forest walk is cheaper: use a file for numbers about the default model.
//
// Counters per run: p50_ms/p90_ms/p99_ms of the boxes, found (fraction with
// a pose), arena_bytes (high-water) and arena_capacity, and the mean time
// per box of each stage (ms_<stage>).
//
// Run: build/bin/bench_estimate [--benchmark_filter=...]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/dataset/bop_dataset.h"
#include "core/estimation/pose_estimator.h"
#include "core/forest/forest_trainer.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/model/forest_file.h"
#include "core/training/hocp_split_metric.h"
#include "core/training/training_set.h"
#include "firmware_app/config/pipeline_config.h"

#ifndef IHF_SHARED_DIR
#define IHF_SHARED_DIR "../shared"
#endif

namespace ihf {
namespace {

[[noreturn]] void die(const std::string &what)
{
	std::fprintf(stderr, "bench_estimate: %s\n", what.c_str());
	std::exit(1);
}

struct Setup {
	std::unique_ptr<ObjectModel> model;
	DepthImageMm depth;
	CameraIntrinsics K;
	PixelBox box;
};

std::unique_ptr<ObjectModel> trainSmall(int objId, const BopDataset &dataset)
{
	auto mesh = dataset.loadModel(objId);
	if (!mesh)
		die(mesh.error().message);
	ModelParams params;
	params.objId = objId;
	params.diameter = meshDiameter(*mesh);
	TrainingSetConfig set;
	set.views.viewpoints = 60;
	set.views.inplaneSteps = 6;
	set.views.minDistance = 850;
	set.views.maxDistance = 1150;
	set.views.seed = 1;
	set.scales = {1.0f, 1.5f};
	set.partsPerImage = 10;
	set.seed = 1;
	set.threads = 2;
	std::fprintf(stderr, "bench_estimate: training a small forest for object %d...\n", objId);
	auto training = buildTrainingSet(*mesh, kinectV1Intrinsics(), params, set);
	if (!training)
		die(training.error().message);
	HocpSplitMetric metric(*training, params.hocp, params.depthCheckMarginMm);
	ForestTrainerConfig fc;
	fc.seed = 1;
	fc.threads = 2;
	HoughForest forest = trainForest(fc, metric, training->labels);
	return std::make_unique<OwnedObjectModel>(params, std::move(*mesh),
						  ForestStorage(forest, TemplateEncoding::kUint8));
}

const Setup &setup()
{
	static Setup s = [] {
		Setup out;
		auto dataset = BopDataset::open(std::string(IHF_SHARED_DIR) + "/data/lmo", "test");
		if (!dataset)
			die(dataset.error().message);
		if (const char *file = std::getenv("IHF_BENCH_FOREST")) {
			auto m = loadModelFile(file);
			if (!m)
				die(m.error().message);
			out.model = std::move(m.value());
		} else {
			const char *obj = std::getenv("IHF_BENCH_OBJ");
			out.model = trainSmall(obj ? std::atoi(obj) : 9, *dataset);
		}
		auto scene = dataset->loadScene(2);
		if (!scene)
			die(scene.error().message);
		const SceneCamera &cam = scene->cameras.at(3);
		auto depth = dataset->loadDepthMm(2, 3, cam.depthScale);
		if (!depth)
			die(depth.error().message);
		out.depth = std::move(*depth);
		out.K = cam.intrinsics;
		out.K.width = out.depth.width();
		out.K.height = out.depth.height();
		const int objId = out.model->params().objId;
		const auto &gt = scene->gt.at(3);
		const auto &info = scene->gtInfo.at(3);
		for (size_t i = 0; i < gt.size(); ++i) {
			if (gt[i].objId != objId)
				continue;
			const auto &b = info[i].bboxObj;
			const double w = 1.1 * b[2], h = 1.1 * b[3];
			out.box = {static_cast<int>(std::floor(b[0] + 0.5 * b[2] - 0.5 * w)),
				   static_cast<int>(std::floor(b[1] + 0.5 * b[3] - 0.5 * h)),
				   static_cast<int>(std::ceil(w)), static_cast<int>(std::ceil(h))};
		}
		if (out.box.empty())
			die("object " + std::to_string(objId) + " is not in LM-O test/000002 image 3");
		if (Status st = app::prepareModel(*out.model, app::EstimateSettings{}); !st)
			die(st.error().message);
		return out;
	}();
	return s;
}

double percentile(std::vector<double> v, double p)
{
	if (v.empty())
		return 0;
	std::sort(v.begin(), v.end());
	return v[static_cast<size_t>(std::floor(p * static_cast<double>(v.size() - 1) + 0.5))];
}

void BM_EstimateBox(benchmark::State &state)
{
	const Setup &s = setup();
	const app::EstimateSettings defaults;
	EstimatorLimits limits = defaults.limits;
	limits.threads = static_cast<int>(state.range(3));
	app::growLimitsFor(limits, *s.model);
	PoseEstimator estimator(limits);
	if (!estimator.valid()) {
		state.SkipWithError("no arena");
		return;
	}
	EstimatorConfig cfg = defaults.estimator;
	cfg.iterations = static_cast<int>(state.range(0));
	cfg.icp = state.range(1) != 0;
	if (!cfg.icp)
		cfg.halfTurns.candidates = 0;
	cfg.frameBudgetMs = static_cast<float>(state.range(2));

	std::vector<double> ms;
	int i = 0, found = 0;
	for (auto _ : state) {
		PixelBox box = s.box;
		box.x += i % 5 - 2;
		box.y += (i / 5) % 5 - 2;
		++i;
		const auto t0 = std::chrono::steady_clock::now();
		PoseEstimate r = estimator.estimate(s.depth.view(), s.K, box, *s.model, cfg);
		const auto t1 = std::chrono::steady_clock::now();
		benchmark::DoNotOptimize(r);
		ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
		found += r.found;
	}
	const EstimatorStats st = estimator.stats();
	state.counters["p50_ms"] = percentile(ms, 0.5);
	state.counters["p90_ms"] = percentile(ms, 0.9);
	state.counters["p99_ms"] = percentile(ms, 0.99);
	state.counters["found"] = ms.empty() ? 0.0 : static_cast<double>(found) / static_cast<double>(ms.size());
	state.counters["arena_bytes"] = static_cast<double>(st.arenaHighWater);
	state.counters["arena_capacity"] = static_cast<double>(st.arenaCapacity);
	state.counters["iters_per_box"] =
		ms.empty() ? 0.0 : static_cast<double>(st.iterations) / static_cast<double>(ms.size());
	for (int k = 0; k < kStageCount; ++k)
		state.counters[std::string("ms_") + stageName(static_cast<Stage>(k))] =
			ms.empty() ? 0.0 : 1e-6 * static_cast<double>(st.stages[k].totalNs) / static_cast<double>(ms.size());
}

// {k, icp, budget ms, threads}
BENCHMARK(BM_EstimateBox)
	->ArgNames({"k", "icp", "budget_ms", "threads"})
	->Args({0, 0, 0, 1})
	->Args({0, 1, 0, 1})
	->Args({5, 0, 0, 1})
	->Args({5, 1, 0, 1})
	->Args({5, 1, 33, 1})
	->Args({0, 1, 0, 2})
	->Args({5, 1, 0, 2})
	->Args({5, 1, 33, 2})
	->Args({5, 1, 10, 2})
	->Iterations(100)
	->Unit(benchmark::kMillisecond);

} // namespace
} // namespace ihf
