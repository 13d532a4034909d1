// SPDX-License-Identifier: MIT
// `ihf train`: renders training views of a mesh, builds the annotated parts
// and grows the Hough forest; writes a forest file.

#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "core/forest/forest_trainer.h"
#include "core/geometry/mesh_import.h"
#include "core/model/forest_file.h"
#include "core/training/hocp_split_metric.h"
#include "core/training/near_symmetry_finder.h"
#include "core/training/training_set.h"
#include "firmware_app/commands/command.h"
#include "firmware_app/config/pipeline_config.h"
#include "firmware_app/commands/progress_bar.h"

namespace ihf::app {

namespace {

struct TrainOptions {
	std::string model;
	std::string out;
	std::string config;
	std::string camera;
	std::string modelsInfo;
	int objId = -1;
	int threads = 0;
	int64_t seed = -1;
};

int runTrain(const TrainOptions &o)
{
	auto settings = loadTrainConfig(o.config);
	if (!settings) {
		std::fprintf(stderr, "ihf train: %s\n", settings.error().message.c_str());
		return kExitFailure;
	}
	TrainSettings &s = *settings;
	if (o.threads > 0)
		s.set.threads = s.forest.threads = o.threads;
	if (o.seed >= 0)
		s.set.seed = s.set.views.seed = s.forest.seed = s.params.seed = static_cast<uint64_t>(o.seed);

	auto mesh = loadMesh(o.model);
	if (!mesh) {
		std::fprintf(stderr, "ihf train: %s\n", mesh.error().message.c_str());
		return kExitFailure;
	}
	size_t degenerate = countDegenerateFaces(*mesh);
	if (degenerate > 0)
		std::fprintf(stderr, "ihf train: %s: %zu degenerate faces ignored\n", o.model.c_str(), degenerate);

	CameraIntrinsics K = kinectV1Intrinsics();
	if (!o.camera.empty()) {
		auto cam = readBopCamera(o.camera);
		if (!cam) {
			std::fprintf(stderr, "ihf train: %s\n", cam.error().message.c_str());
			return kExitFailure;
		}
		K = cam->intrinsics;
	}

	int objId = o.objId;
	if (objId < 0)
		objId = modelObjId(std::filesystem::path(o.model).stem().string()).value_or(-1);
	if (objId < 0) {
		std::fprintf(stderr, "ihf train: cannot tell the object id from %s; pass --obj-id\n",
			     o.model.c_str());
		return kExitUsage;
	}
	s.params.objId = objId;
	s.params.diameter = meshDiameter(*mesh);
	// Coordinates are millimetres in every format; an object a few mm
	// across is most likely a model exported in metres (glTF's unit).
	if (s.params.diameter < 5.0)
		std::fprintf(stderr, "ihf train: warning: %s is %.3g mm across; coordinates are read as millimetres "
			     "(scale a model in metres by 1000)\n", o.model.c_str(), s.params.diameter);
	s.params.meshName = std::filesystem::path(o.model).filename().string();
	std::filesystem::path infoPath = o.modelsInfo.empty()
		? std::filesystem::path(o.model).parent_path() / "models_info.json"
		: std::filesystem::path(o.modelsInfo);
	if (std::filesystem::exists(infoPath)) {
		auto info = readModelsInfo(infoPath);
		if (!info) {
			std::fprintf(stderr, "ihf train: %s\n", info.error().message.c_str());
			return kExitFailure;
		}
		if (auto it = info->find(objId); it != info->end())
			s.params.symmetric = it->second.symmetric();
	}
	s.params.trainScales = s.set.scales;

	const auto t0 = std::chrono::steady_clock::now();
	ProgressBar viewsBar("views ");
	auto set = buildTrainingSet(*mesh, K, s.params, s.set,
				    [&](int d, int t) { viewsBar.update(d, t); });
	if (!set) {
		std::fprintf(stderr, "ihf train: %s\n", set.error().message.c_str());
		return kExitFailure;
	}
	const auto t1 = std::chrono::steady_clock::now();
	HocpSplitMetric metric(*set, s.params.hocp, s.params.depthCheckMarginMm);
	ProgressBar forestBar("forest");
	HoughForest forest = trainForest(s.forest, metric, set->labels,
					 [&](size_t d, size_t t) { forestBar.update(d, t); });
	const auto t2 = std::chrono::steady_clock::now();

	s.params.trainViews = set->views;
	s.params.trainSamples = static_cast<int>(set->samples.size());
	s.params.trainSeconds = std::chrono::duration<double>(t2 - t0).count();
	ForestStorage storage(forest, s.encoding);
	if (!storage.error().empty()) {
		std::fprintf(stderr, "ihf train: %s\n", storage.error().c_str());
		return kExitFailure;
	}
	// Nothing after training reads vertex normals (rendering and the view
	// templates use the faces): the file leaves them out.
	mesh->normals.clear();
	const std::vector<NearSymmetry> nearSymmetries = findNearSymmetries(*mesh);
	for (const NearSymmetry &ns : nearSymmetries)
		std::fprintf(stderr, "ihf train: near-symmetry: %s\n", describeNearSymmetry(ns).c_str());
	if (auto st = saveModelFile(o.out, s.params, *mesh, storage.view(), nearSymmetries); !st) {
		std::fprintf(stderr, "ihf train: %s\n", st.error().message.c_str());
		return kExitFailure;
	}
	std::fprintf(stderr,
		     "ihf train: object %d: %d views (%d skipped), %zu parts, %zu nodes; "
		     "parts %.1fs, forest %.1fs; wrote %s (%.2f MB)\n",
		     objId, set->views, set->skippedViews, set->samples.size(), forest.nodeCount(),
		     std::chrono::duration<double>(t1 - t0).count(),
		     std::chrono::duration<double>(t2 - t1).count(), o.out.c_str(),
		     std::filesystem::file_size(o.out) / 1e6);
	return kExitOk;
}

} // namespace

void addTrainCommand(CLI::App &root, Action &action)
{
	auto opts = std::make_shared<TrainOptions>();
	auto *cmd = root.add_subcommand("train", "Train an IHF forest from an object mesh");
	cmd->add_option("--model", opts->model,
			std::string("Object mesh in mm (") + meshImportFormats() + "), e.g. models/obj_000001.ply")
		->required()->check(CLI::ExistingFile);
	cmd->add_option("--out", opts->out, "Forest file to write (.ihf)")->required();
	cmd->add_option("--config", opts->config, "Training configuration (TOML), e.g. config/train.toml")
		->check(CLI::ExistingFile);
	cmd->add_option("--camera", opts->camera, "BOP camera.json of the target camera (default: Kinect v1 of LM-O)")
		->check(CLI::ExistingFile);
	cmd->add_option("--models-info", opts->modelsInfo, "models_info.json (default: beside the mesh)");
	cmd->add_option("--obj-id", opts->objId, "Object id (default: from the file name obj_NNNNNN.*)");
	cmd->add_option("--threads", opts->threads, "Worker threads (default: from config)")->check(CLI::Range(1, 256));
	cmd->add_option("--seed", opts->seed, "Random seed (default: from config)")->check(CLI::NonNegativeNumber);
	cmd->callback([opts, &action] { action = [opts] { return runTrain(*opts); }; });
}

} // namespace ihf::app
