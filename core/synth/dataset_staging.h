// SPDX-License-Identifier: MIT
#pragma once

// What every synthetic set's writer shares: its camera, the refusal to
// replace an existing set unasked, and the hidden sibling folder the set is
// built in (".NAME.synth-PID") and renamed from into place at the end, so
// that a failure leaves nothing at the output path.

#include <filesystem>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "core/dataset/bop_types.h"
#include "core/synth/model_library.h"

namespace ihf {

// "%06d": BOP's scene and image file names.
std::string sixDigits(int v);

// The Kinect v1 intrinsics, or those of a BOP camera.json, with depthScale.
Expected<BopCamera> synthCamera(const std::filesystem::path &cameraFile, double depthScale);

// An error unless out is free or overwrite is set.
Status checkOutputFree(const std::filesystem::path &out, bool overwrite);

class StagingFolder
{
public:
	// Creates the staging folder beside out (an old one is removed).
	static Expected<StagingFolder> create(const std::filesystem::path &out);

	StagingFolder(StagingFolder &&other) noexcept : dir_(std::move(other.dir_)) { other.dir_.clear(); }
	StagingFolder &operator=(StagingFolder &&) = delete;
	StagingFolder(const StagingFolder &) = delete;
	~StagingFolder(); // removes the folder unless committed

	const std::filesystem::path &dir() const { return dir_; }

	// Copies the meshes of ids to models/ and writes camera.json and
	// models/models_info.json.
	Status addModels(const ModelLibrary &library, const std::vector<int> &ids,
			 const BopCamera &camera);

	// Replaces out with the staged set.
	Status commit(const std::filesystem::path &out);

private:
	explicit StagingFolder(std::filesystem::path dir) : dir_(std::move(dir)) {}
	std::filesystem::path dir_;
};

} // namespace ihf
