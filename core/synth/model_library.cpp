// SPDX-License-Identifier: MIT
#include "core/synth/model_library.h"

#include <cstdio>

#include "core/dataset/bop_io.h"
#include "core/geometry/ply_loader.h"
#include "core/synth/synth_random.h"

namespace ihf {

int sampleRestingPose(const PlaceableModel &model, SynthRandom &rng)
{
	double u = rng.uniform01();
	for (size_t i = 0; i < model.restingPoses.size(); ++i) {
		u -= model.restingPoses[i].probability;
		if (u < 0)
			return static_cast<int>(i);
	}
	return static_cast<int>(model.restingPoses.size()) - 1;
}

int uprightRestingPose(const PlaceableModel &model)
{
	int best = 0;
	for (size_t i = 1; i < model.restingPoses.size(); ++i)
		if (model.restingPoses[i].R(2, 2) > model.restingPoses[best].R(2, 2))
			best = static_cast<int>(i);
	return best;
}

PlaceableModel primitiveModel(Mesh mesh)
{
	PlaceableModel m;
	RestingPose rest;
	rotatedBounds(mesh, rest.R, rest.min, rest.max);
	m.diameter = (rest.max - rest.min).norm();
	m.restingPoses.push_back(rest);
	m.mesh = std::make_shared<const Mesh>(std::move(mesh));
	return m;
}

std::filesystem::path ModelLibrary::plyPath(int objId) const
{
	char name[32];
	std::snprintf(name, sizeof(name), "obj_%06d.ply", objId);
	return dir_ / name;
}

std::vector<int> ModelLibrary::ids() const
{
	std::vector<int> ids;
	for (const auto &[id, m] : models_)
		ids.push_back(id);
	return ids;
}

size_t ModelLibrary::maxVertices() const
{
	size_t n = 0;
	for (const auto &[id, m] : models_)
		n = std::max(n, m.mesh->vertices.size());
	return n;
}

Expected<ModelLibrary> ModelLibrary::load(const std::filesystem::path &dir,
					  const std::vector<int> &required)
{
	std::error_code ec;
	if (!std::filesystem::is_directory(dir, ec))
		return makeError(Errc::kNotFound, dir.string() + ": models folder not found");
	const auto infoFile = dir / "models_info.json";
	if (!std::filesystem::exists(infoFile, ec))
		return makeError(Errc::kNotFound, infoFile.string() + ": file not found");
	auto info = readModelsInfo(infoFile);
	if (!info)
		return info.error();

	ModelLibrary lib;
	lib.dir_ = dir;
	lib.info_ = std::move(*info);
	for (int id : required) {
		if (!lib.info_.count(id))
			return makeError(Errc::kNotFound, infoFile.string() + ": object id " +
							  std::to_string(id) + " not listed");
		if (!std::filesystem::exists(lib.plyPath(id), ec))
			return makeError(Errc::kNotFound, lib.plyPath(id).string() +
							  ": mesh of object " + std::to_string(id) +
							  " not found");
	}
	for (const auto &[id, mi] : lib.info_) {
		const auto path = lib.plyPath(id);
		if (!std::filesystem::exists(path, ec))
			continue; // listed but absent: not usable as a distractor either
		auto mesh = loadPly(path);
		if (!mesh)
			return mesh.error();
		if (mesh->vertices.empty() || mesh->faces.empty())
			return makeError(Errc::kCorrupt, path.string() + ": mesh has no faces");
		PlaceableModel m;
		m.objId = id;
		m.diameter = mi.diameter > 0 ? mi.diameter : meshDiameter(*mesh);
		auto poses = computeRestingPoses(*mesh);
		if (!poses)
			return makeError(poses.error().code, path.string() + ": " + poses.error().message);
		if (poses->empty())
			return makeError(Errc::kCorrupt, path.string() + ": no resting pose found");
		m.restingPoses = std::move(*poses);
		m.mesh = std::make_shared<const Mesh>(std::move(*mesh));
		lib.models_.emplace(id, std::move(m));
	}
	return lib;
}

} // namespace ihf
