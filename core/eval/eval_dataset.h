// SPDX-License-Identifier: MIT
#pragma once

// `ihf eval` on a BOP dataset: gathers the ground truth of one split, the
// models and their info, checks the results rows, and scores them with
// evaluatePoses() (see evaluation.h for the semantics).
//
// - Evaluated objects: `objects` if not empty, else every object id in the
//   results. Each needs a models_info.json entry with a positive diameter and
//   a model with vertices.
// - Ground truths: every scene_gt.json instance of an evaluated object in
//   every image of the split; with `targets`, only those of the
//   (scene, image, object) triples that have a box.
// - Estimates: the results rows of evaluated objects; with `targets`, rows
//   of other triples are ignored (counted in numIgnored), as BOP does.
//   A row naming an image that is not in the split is an error.
// - Visible surface (request.visibleSurface): e_VSD of every estimate
//   against every instance of its object in its image, from the image's
//   depth (SPLIT/SCENE/depth/IM.png, which must be there) and camera
//   (scene_camera.json), for AR_VSD (evaluation.h, visible_surface.h).

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "core/common/expected.h"
#include "core/dataset/bop_dataset.h"
#include "core/eval/evaluation.h"

namespace ihf {

struct EvalRequest {
	std::vector<int> objects; // empty: every object in the results
	std::optional<std::vector<Detection>> targets;
	std::filesystem::path resultsFile;  // named in messages
	std::filesystem::path targetsFile;  // named in messages
	std::vector<double> zValues = defaultZValues();
	bool visibleSurface = false; // also AR_VSD (reads the depth images)
};

// The scoring of each object: its diameter (models_info.json, which must
// list it with a positive diameter) and its error function over every vertex
// of its model, ADI when models_info.json lists symmetries, else ADD; with
// keepMeshes also the meshes themselves (the visible surface renders them).
struct EvalModels {
	std::map<int, EvalObject> objects; // points into `errors`
	std::map<int, std::unique_ptr<ObjectPoseError>> errors;
	std::map<int, Mesh> meshes; // with keepMeshes only
};

Expected<EvalModels> loadEvalModels(const BopDataset &dataset, const std::set<int> &objectIds,
				    bool keepMeshes = false);

// The models_info.json part of loadEvalModels alone: an entry with a
// positive diameter for each object (cheap; checked before anything is read).
Status checkDiameters(const BopDataset &dataset, const std::set<int> &objectIds);

Expected<EvalReport> evaluateOnDataset(const BopDataset &dataset,
				       const std::vector<ResultRow> &results,
				       const EvalRequest &request);

} // namespace ihf
