// SPDX-License-Identifier: MIT
#include "core/synth/dataset_staging.h"

#include <cstdio>
#include <map>

#include <unistd.h>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"

namespace ihf {

namespace fs = std::filesystem;

std::string sixDigits(int v)
{
	char b[16];
	std::snprintf(b, sizeof(b), "%06d", v);
	return b;
}

Expected<BopCamera> synthCamera(const fs::path &cameraFile, double depthScale)
{
	BopCamera camera;
	camera.intrinsics = kinectV1Intrinsics();
	if (!cameraFile.empty()) {
		auto cam = readBopCamera(cameraFile);
		if (!cam)
			return cam.error();
		camera = *cam;
		if (!camera.intrinsics.valid())
			return makeError(Errc::kInvalidArgument, cameraFile.string() + ": invalid intrinsics");
	}
	camera.depthScale = depthScale;
	return camera;
}

Status checkOutputFree(const fs::path &out, bool overwrite)
{
	std::error_code ec;
	if (fs::exists(out, ec) && !overwrite)
		return makeError(Errc::kInvalidArgument,
				 out.string() + ": already exists (use --overwrite to replace it)");
	return {};
}

Expected<StagingFolder> StagingFolder::create(const fs::path &out)
{
	std::error_code ec;
	fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
	if (!fs::is_directory(parent, ec))
		return makeError(Errc::kNotFound, parent.string() + ": output's parent folder not found");
	std::string name = ".";
	name += out.filename().string();
	name += ".synth-";
	name += std::to_string(::getpid());
	const fs::path staging = parent / name;
	fs::remove_all(staging, ec);
	StagingFolder folder(staging);
	fs::create_directories(staging / "models", ec);
	if (ec)
		return makeError(Errc::kIo, staging.string() + ": " + ec.message());
	return folder;
}

StagingFolder::~StagingFolder()
{
	if (!dir_.empty()) {
		std::error_code ec;
		fs::remove_all(dir_, ec);
	}
}

Status StagingFolder::addModels(const ModelLibrary &library, const std::vector<int> &ids,
				const BopCamera &camera)
{
	std::error_code ec;
	std::map<int, ModelInfo> info;
	for (int id : ids) {
		info[id] = library.info().at(id);
		fs::copy_file(library.plyPath(id), dir_ / "models" / library.plyPath(id).filename(),
			      fs::copy_options::overwrite_existing, ec);
		if (ec)
			return makeError(Errc::kIo, library.plyPath(id).string() + ": copy failed: " +
							    ec.message());
	}
	return createBopDataset(dir_, camera, info);
}

Status StagingFolder::commit(const fs::path &out)
{
	std::error_code ec;
	if (fs::exists(out, ec)) {
		fs::remove_all(out, ec);
		if (ec)
			return makeError(Errc::kIo, out.string() + ": cannot replace: " + ec.message());
	}
	fs::rename(dir_, out, ec);
	if (ec)
		return makeError(Errc::kIo, out.string() + ": cannot move the set into place: " +
						    ec.message());
	dir_.clear();
	return {};
}

} // namespace ihf
