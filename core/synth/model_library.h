// SPDX-License-Identifier: MIT
#pragma once

// The meshes a synthetic scene can stand on its table: the BOP models of a
// models folder (targets, and distractors for the other targets) and
// procedural primitives, each with its resting poses.

#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "core/common/expected.h"
#include "core/dataset/bop_types.h"
#include "core/geometry/mesh.h"
#include "core/synth/resting_poses.h"

namespace ihf {

struct PlaceableModel {
	std::shared_ptr<const Mesh> mesh;
	std::vector<RestingPose> restingPoses; // at least one
	int objId = 0; // BOP object id; 0 for primitives
	double diameter = 0; // mm
};

// Picks a resting pose index with the poses' probabilities.
class SynthRandom;
int sampleRestingPose(const PlaceableModel &model, SynthRandom &rng);

// The resting pose that keeps the model's +z axis most nearly up: how a
// person sets an object down (BOP models of household objects are modelled
// z-up, and LINEMOD's scenes show them that way).
int uprightRestingPose(const PlaceableModel &model);

// Wraps a primitive built in its resting frame (standing on z = 0).
PlaceableModel primitiveModel(Mesh mesh);

class ModelLibrary
{
public:
	// Reads DIR/models_info.json and every obj_NNNNNN.ply it lists. The ids
	// in required must all be present.
	static Expected<ModelLibrary> load(const std::filesystem::path &dir,
					   const std::vector<int> &required);

	const std::filesystem::path &dir() const { return dir_; }
	const std::map<int, ModelInfo> &info() const { return info_; }
	const PlaceableModel &model(int objId) const { return models_.at(objId); }
	std::vector<int> ids() const;
	std::filesystem::path plyPath(int objId) const;
	size_t maxVertices() const;

private:
	std::filesystem::path dir_;
	std::map<int, ModelInfo> info_;
	std::map<int, PlaceableModel> models_;
};

} // namespace ihf
