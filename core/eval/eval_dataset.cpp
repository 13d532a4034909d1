// SPDX-License-Identifier: MIT
#include "core/eval/eval_dataset.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <tuple>

#include "core/eval/visible_surface.h"

namespace ihf {

namespace {

using Triple = std::tuple<int, int, int>; // scene, image, object

std::string rowName(const std::filesystem::path &file, size_t index, const ResultRow &row)
{
	return file.string() + ": data row " + std::to_string(index + 1) + " (scene_id " +
	       std::to_string(row.sceneId) + ", im_id " + std::to_string(row.imId) +
	       ", obj_id " + std::to_string(row.objId) + ")";
}

using ImageKey = std::pair<int, int>; // scene, image

// e_VSD of every estimate against every instance of its object in its
// image, one image at a time (its depth read once), images shared out over
// the cores.
Expected<VsdErrors> scoreVisibleSurfaces(const BopDataset &dataset,
					 const std::map<ImageKey, SceneCamera> &cameras,
					 const std::vector<EvalGt> &gts,
					 const std::vector<ResultRow> &estimates)
{
	VsdErrors vsd;
	vsd.tauShares = vsdTauShares();
	vsd.thetas = vsdThetas();

	struct ImageWork {
		ImageKey image;
		std::vector<std::pair<size_t, size_t>> pairs; // estimate, instance
	};
	std::map<ImageKey, ImageWork> byImage;
	std::map<std::tuple<int, int, int>, std::vector<size_t>> gtsOf;
	for (size_t g = 0; g < gts.size(); ++g)
		gtsOf[{gts[g].sceneId, gts[g].imId, gts[g].objId}].push_back(g);
	std::set<int> objectIds;
	for (size_t e = 0; e < estimates.size(); ++e) {
		const ResultRow &row = estimates[e];
		auto it = gtsOf.find({row.sceneId, row.imId, row.objId});
		if (it == gtsOf.end())
			continue;
		if (!cameras.count({row.sceneId, row.imId}))
			return makeError(Errc::kNotFound,
					 (dataset.sceneDir(row.sceneId) / "scene_camera.json").string() +
						 ": no entry for image " + std::to_string(row.imId));
		ImageWork &work = byImage[{row.sceneId, row.imId}];
		work.image = {row.sceneId, row.imId};
		for (size_t g : it->second)
			work.pairs.push_back({e, g});
		objectIds.insert(row.objId);
	}

	std::map<int, Mesh> meshes;
	for (int id : objectIds) {
		Expected<Mesh> mesh = dataset.loadModel(id);
		if (!mesh)
			return mesh.error();
		meshes[id] = std::move(*mesh);
	}

	std::vector<const ImageWork *> work;
	for (const auto &[key, w] : byImage)
		work.push_back(&w);
	std::atomic<size_t> next{0};
	std::mutex lock;
	std::optional<Error> failure;
	auto run = [&] {
		std::map<int, std::unique_ptr<VisibleSurfaceScorer>> scorers;
		for (size_t i = next++; i < work.size(); i = next++) {
			const auto [sceneId, imId] = work[i]->image;
			const SceneCamera &camera = cameras.at(work[i]->image);
			Expected<DepthImageMm> depth = dataset.loadDepthMm(sceneId, imId, camera.depthScale);
			if (!depth) {
				std::lock_guard guard(lock);
				failure = depth.error();
				return;
			}
			for (const auto &[e, g] : work[i]->pairs) {
				const int objId = estimates[e].objId;
				std::unique_ptr<VisibleSurfaceScorer> &scorer = scorers[objId];
				if (!scorer)
					scorer = std::make_unique<VisibleSurfaceScorer>(meshes.at(objId));
				std::vector<double> taus;
				for (double share : vsd.tauShares)
					taus.push_back(share * dataset.modelsInfo().at(objId).diameter);
				Expected<std::vector<double>> errors = scorer->errors(
					estimates[e].pose, gts[g].pose, depth->view(), camera.intrinsics, taus);
				std::lock_guard guard(lock);
				if (!errors) {
					failure = makeError(errors.error().code,
							    dataset.depthPath(sceneId, imId).string() + ": " +
								    errors.error().message);
					return;
				}
				vsd.errors[{e, g}] = std::move(*errors);
			}
		}
	};
	const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
	std::vector<std::thread> threads;
	for (size_t t = 1; t < std::min<size_t>(cores, work.size()); ++t)
		threads.emplace_back(run);
	run();
	for (std::thread &t : threads)
		t.join();
	if (failure)
		return *failure;
	return vsd;
}

} // namespace

Status checkDiameters(const BopDataset &dataset, const std::set<int> &objectIds)
{
	const std::filesystem::path infoFile = dataset.root() / "models" / "models_info.json";
	const std::map<int, ModelInfo> &info = dataset.modelsInfo();
	for (int id : objectIds) {
		if (!info.count(id))
			return makeError(Errc::kNotFound, "object " + std::to_string(id) + ": no entry in " +
								  infoFile.string());
		const double d = info.at(id).diameter;
		if (!(d > 0) || !std::isfinite(d))
			return makeError(Errc::kParse,
					 infoFile.string() + ": \"" + std::to_string(id) +
						 "\".diameter must be a positive number");
	}
	return {};
}

Expected<EvalModels> loadEvalModels(const BopDataset &dataset, const std::set<int> &objectIds)
{
	if (Status s = checkDiameters(dataset, objectIds); !s)
		return s.error();
	const std::map<int, ModelInfo> &info = dataset.modelsInfo();
	EvalModels models;
	for (int id : objectIds) {
		Expected<Mesh> mesh = dataset.loadModel(id);
		if (!mesh)
			return mesh.error();
		if (mesh->vertices.empty())
			return makeError(Errc::kCorrupt,
					 dataset.modelPath(id).string() + ": model has no vertices");
		const PoseMetric metric = info.at(id).symmetric() ? PoseMetric::kAdi : PoseMetric::kAdd;
		auto error = std::make_unique<ObjectPoseError>(std::move(mesh->vertices), metric);
		models.objects[id] = {info.at(id).diameter, error.get()};
		models.errors[id] = std::move(error);
	}
	return models;
}

Expected<EvalReport> evaluateOnDataset(const BopDataset &dataset,
				       const std::vector<ResultRow> &results,
				       const EvalRequest &request)
{
	const std::filesystem::path infoFile = dataset.root() / "models" / "models_info.json";
	const std::map<int, ModelInfo> &info = dataset.modelsInfo();

	// Which objects, each with a models_info entry.
	std::set<int> objectIds;
	if (!request.objects.empty()) {
		for (int id : request.objects) {
			if (!info.count(id))
				return makeError(Errc::kNotFound,
						 "object " + std::to_string(id) + " (--objects): no entry in " +
							 infoFile.string());
			objectIds.insert(id);
		}
	} else {
		for (size_t i = 0; i < results.size(); ++i) {
			const ResultRow &row = results[i];
			if (!info.count(row.objId))
				return makeError(Errc::kNotFound,
						 rowName(request.resultsFile, i, row) + ": obj_id " +
							 std::to_string(row.objId) + " has no entry in " +
							 infoFile.string());
			objectIds.insert(row.objId);
		}
	}
	if (Status s = checkDiameters(dataset, objectIds); !s)
		return s.error();

	std::set<Triple> targeted;
	if (request.targets) {
		for (const Detection &det : *request.targets)
			targeted.insert({det.sceneId, det.imageId, det.categoryId});
	}

	// Ground truth of the split; also the set of its images.
	std::vector<EvalGt> gts;
	std::set<std::pair<int, int>> images;
	std::map<ImageKey, SceneCamera> cameras;
	for (int sceneId : dataset.sceneIds()) {
		Expected<BopScene> scene = dataset.loadScene(sceneId);
		if (!scene)
			return scene.error();
		for (const auto &[imId, cam] : scene->cameras) {
			images.insert({sceneId, imId});
			cameras[{sceneId, imId}] = cam;
		}
		for (const auto &[imId, instances] : scene->gt) {
			images.insert({sceneId, imId});
			for (const GtInstance &inst : instances) {
				if (!objectIds.count(inst.objId))
					continue;
				if (request.targets && !targeted.count({sceneId, imId, inst.objId}))
					continue;
				gts.push_back({sceneId, imId, inst.objId, inst.pose});
			}
		}
	}

	if (request.targets) {
		for (size_t i = 0; i < request.targets->size(); ++i) {
			const Detection &det = (*request.targets)[i];
			if (!images.count({det.sceneId, det.imageId}))
				return makeError(Errc::kNotFound,
						 request.targetsFile.string() + ": entry " + std::to_string(i) +
							 " (scene_id " + std::to_string(det.sceneId) +
							 ", image_id " + std::to_string(det.imageId) +
							 "): image not in split \"" + dataset.split() + "\" of " +
							 dataset.root().string());
		}
	}

	// The rows to score.
	std::vector<ResultRow> estimates;
	size_t ignored = 0;
	for (size_t i = 0; i < results.size(); ++i) {
		const ResultRow &row = results[i];
		if (!objectIds.count(row.objId))
			continue;
		if (!images.count({row.sceneId, row.imId}))
			return makeError(Errc::kNotFound,
					 rowName(request.resultsFile, i, row) + ": image not in split \"" +
						 dataset.split() + "\" of " + dataset.root().string());
		if (!std::isfinite(row.score))
			return makeError(Errc::kParse,
					 rowName(request.resultsFile, i, row) + ": score is not a finite number");
		if (!row.pose.R.allFinite() || !row.pose.t.allFinite())
			return makeError(Errc::kParse,
					 rowName(request.resultsFile, i, row) + ": R or t is not finite");
		if (request.targets && !targeted.count({row.sceneId, row.imId, row.objId})) {
			++ignored;
			continue;
		}
		estimates.push_back(row);
	}

	Expected<EvalModels> models = loadEvalModels(dataset, objectIds);
	if (!models)
		return models.error();
	std::optional<VsdErrors> vsd;
	if (request.visibleSurface) {
		Expected<VsdErrors> scored = scoreVisibleSurfaces(dataset, cameras, gts, estimates);
		if (!scored)
			return scored.error();
		vsd = std::move(*scored);
	}
	EvalReport report = evaluatePoses(models->objects, gts, estimates, request.zValues,
					  vsd ? &*vsd : nullptr);
	report.numIgnored = ignored;
	return report;
}

} // namespace ihf
