// SPDX-License-Identifier: MIT
#include "core/eval/eval_dataset.h"

#include <cmath>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>

#include "core/eval/visible_surface.h"
#include "core/runtime/worker_pool.h"

namespace ihf {

namespace {

using Triple = std::tuple<int, int, int>; // scene, image, object

std::string rowName(const std::filesystem::path &file, size_t index, const ResultRow &row)
{
	return file.string() + ": data row " + std::to_string(index + 1) + " (scene_id " +
	       std::to_string(row.sceneId) + ", im_id " + std::to_string(row.imId) +
	       ", obj_id " + std::to_string(row.objId) + ")";
}

using ImageKey = std::pair<int, int>;        // scene, image
using PairKey = std::pair<size_t, size_t>;    // estimate, instance

// The pairs of one image whose visible surfaces are compared.
struct ImageWork {
	ImageKey image;
	std::vector<PairKey> pairs;
};

// Every estimate with every instance of its object in its image, image by
// image.
Expected<std::vector<ImageWork>> visibleSurfacePairs(const BopDataset &dataset,
						     const std::map<ImageKey, SceneCamera> &cameras,
						     const std::vector<EvalGt> &gts,
						     const std::vector<ResultRow> &estimates)
{
	std::map<std::tuple<int, int, int>, std::vector<size_t>> gtsOf;
	for (size_t g = 0; g < gts.size(); ++g)
		gtsOf[{gts[g].sceneId, gts[g].imId, gts[g].objId}].push_back(g);
	std::map<ImageKey, ImageWork> byImage;
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
	}
	std::vector<ImageWork> out;
	for (auto &[key, work] : byImage)
		out.push_back(std::move(work));
	return out;
}

// What scoring an image needs of its objects: the model and tau in mm.
struct VsdObject {
	const Mesh *mesh = nullptr;
	std::vector<double> tausMm;
};

// e_VSD of one image's pairs, from its depth read once.
Expected<std::vector<std::pair<PairKey, std::vector<double>>>>
scoreImage(const BopDataset &dataset, const ImageWork &work, const SceneCamera &camera,
	   const std::map<int, VsdObject> &objects, const std::vector<EvalGt> &gts,
	   const std::vector<ResultRow> &estimates)
{
	const auto [sceneId, imId] = work.image;
	Expected<DepthImageMm> depth = dataset.loadDepthMm(sceneId, imId, camera.depthScale);
	if (!depth)
		return depth.error();
	std::map<int, std::unique_ptr<VisibleSurfaceScorer>> scorers;
	std::vector<std::pair<PairKey, std::vector<double>>> out;
	for (const auto &[e, g] : work.pairs) {
		const int objId = estimates[e].objId;
		const VsdObject &object = objects.at(objId);
		std::unique_ptr<VisibleSurfaceScorer> &scorer = scorers[objId];
		if (!scorer)
			scorer = std::make_unique<VisibleSurfaceScorer>(*object.mesh);
		Expected<std::vector<double>> errors =
			scorer->errors(estimates[e].pose, gts[g].pose, depth->view(), camera.intrinsics, object.tausMm);
		if (!errors)
			return makeError(errors.error().code,
					 dataset.depthPath(sceneId, imId).string() + ": " + errors.error().message);
		out.push_back({{e, g}, std::move(*errors)});
	}
	return out;
}

// e_VSD of every estimate against every instance of its object in its
// image, the images shared out over the cores.
Expected<VsdErrors> scoreVisibleSurfaces(const BopDataset &dataset,
					 const std::map<ImageKey, SceneCamera> &cameras,
					 const std::map<int, Mesh> &meshes,
					 const std::vector<EvalGt> &gts,
					 const std::vector<ResultRow> &estimates)
{
	Expected<std::vector<ImageWork>> work = visibleSurfacePairs(dataset, cameras, gts, estimates);
	if (!work)
		return work.error();
	VsdErrors vsd;
	vsd.tauShares = vsdTauShares();
	vsd.thetas = vsdThetas();
	std::map<int, VsdObject> objects;
	for (const auto &[id, mesh] : meshes) {
		VsdObject &object = objects[id];
		object.mesh = &mesh;
		for (double share : vsd.tauShares)
			object.tausMm.push_back(share * dataset.modelsInfo().at(id).diameter);
	}

	// Each image's pairs scored on the pool's threads, the results and the
	// first failure taken in image order.
	std::vector<std::vector<std::pair<PairKey, std::vector<double>>>> scored(work->size());
	std::vector<std::optional<Error>> failures(work->size());
	WorkerPool pool(0);
	pool.run(static_cast<int>(work->size()), [&](int i, int) {
		const size_t k = static_cast<size_t>(i);
		const ImageWork &w = (*work)[k];
		auto image = scoreImage(dataset, w, cameras.at(w.image), objects, gts, estimates);
		if (image)
			scored[k] = std::move(*image);
		else
			failures[k] = image.error();
	});
	for (size_t k = 0; k < work->size(); ++k) {
		if (failures[k])
			return *failures[k];
		for (auto &[key, errors] : scored[k])
			vsd.errors[key] = std::move(errors);
	}
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

Expected<EvalModels> loadEvalModels(const BopDataset &dataset, const std::set<int> &objectIds, bool keepMeshes)
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
		auto error = std::make_unique<ObjectPoseError>(
			keepMeshes ? mesh->vertices : std::move(mesh->vertices), metric);
		models.objects[id] = {info.at(id).diameter, error.get()};
		models.errors[id] = std::move(error);
		if (keepMeshes)
			models.meshes[id] = std::move(*mesh);
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

	Expected<EvalModels> models = loadEvalModels(dataset, objectIds, request.visibleSurface);
	if (!models)
		return models.error();
	std::optional<VsdErrors> vsd;
	if (request.visibleSurface) {
		Expected<VsdErrors> scored = scoreVisibleSurfaces(dataset, cameras, models->meshes, gts, estimates);
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
