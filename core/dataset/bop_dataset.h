// SPDX-License-Identifier: MIT
#pragma once

// A BOP dataset on disk: ROOT/camera.json, ROOT/models/{models_info.json,
// obj_NNNNNN.ply}, ROOT/SPLIT/SCENE(6 digits)/{scene_*.json, depth/IM.png}.

#include <filesystem>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/dataset/bop_types.h"
#include "core/geometry/mesh.h"

namespace ihf {

class BopDataset
{
public:
	// Opens ROOT and reads camera.json and models/models_info.json (if any).
	// split defaults to the first of "test", "val", "train" that exists, or
	// "test" if none does (a fresh skeleton to fill with saveScene()); a split
	// named explicitly must exist.
	static Expected<BopDataset> open(const std::filesystem::path &root,
					 const std::string &split = "");

	const std::filesystem::path &root() const { return root_; }
	const std::string &split() const { return split_; }
	const BopCamera &camera() const { return camera_; }
	const std::map<int, ModelInfo> &modelsInfo() const { return modelsInfo_; }

	// Scene folders (six-digit names) of the split, ascending.
	std::vector<int> sceneIds() const;
	// scene_camera.json and scene_gt.json are required, scene_gt_info.json
	// optional (but must match scene_gt.json entry for entry). Camera
	// width/height come from camera.json. For evaluation, which needs the
	// ground truth: loadSceneCameras() then loadSceneGt().
	Expected<BopScene> loadScene(int sceneId) const;
	// scene_camera.json alone, all that estimation needs: gt and gtInfo stay
	// empty (BOP test splits and a user's own scenes have no scene_gt.json).
	Expected<BopScene> loadSceneCameras(int sceneId) const;
	// Adds scene_gt.json (required) and scene_gt_info.json (if present) to a
	// scene from loadSceneCameras(); on an error the scene is left unchanged.
	Status loadSceneGt(BopScene &scene) const;
	// Writes the scene's JSON files into sceneDir() (gt_info only if not empty).
	Status saveScene(const BopScene &scene) const;

	std::filesystem::path sceneDir(int sceneId) const;
	std::filesystem::path depthPath(int sceneId, int imId) const;
	std::filesystem::path modelPath(int objId) const;

	// Depth in millimetres (raw * depth_scale of the image, 0 = no data).
	Expected<DepthImageMm> loadDepthMm(int sceneId, int imId, double depthScale) const;
	Expected<Mesh> loadModel(int objId) const;

private:
	std::filesystem::path root_;
	std::string split_;
	BopCamera camera_;
	std::map<int, ModelInfo> modelsInfo_;
};

// The object id of a BOP model file name's stem ("obj_000005" -> 5,
// modelPath's inverse); nullopt for any other name.
std::optional<int> modelObjId(std::string_view stem);

// Writes a dataset skeleton: ROOT/camera.json and models_info.json.
Status createBopDataset(const std::filesystem::path &root, const BopCamera &camera,
			const std::map<int, ModelInfo> &modelsInfo);

} // namespace ihf
