// SPDX-License-Identifier: MIT
#include "core/dataset/bop_dataset.h"

#include <algorithm>
#include <charconv>
#include <cstdio>

#include "core/dataset/bop_io.h"
#include "core/geometry/ply_loader.h"

namespace ihf {

namespace {

std::string sixDigits(int id)
{
	char buf[16];
	std::snprintf(buf, sizeof(buf), "%06d", id);
	return buf;
}

bool isSixDigits(const std::string &name)
{
	if (name.size() != 6)
		return false;
	for (char c : name)
		if (c < '0' || c > '9')
			return false;
	return true;
}

// scene_gt_info.json lists one entry per scene_gt.json instance, same order.
Status checkGtInfoMatches(const std::map<int, std::vector<GtInstance>> &gt,
			  const std::map<int, std::vector<GtInfo>> &info,
			  const fs::path &gtFile, const fs::path &infoFile)
{
	for (const auto &[imId, infos] : info) {
		auto it = gt.find(imId);
		size_t gtCount = it == gt.end() ? 0 : it->second.size();
		if (infos.size() != gtCount)
			return makeError(Errc::kCorrupt,
					 infoFile.string() + ": \"" + std::to_string(imId) + "\": " +
						 std::to_string(infos.size()) + " entries but " +
						 gtFile.string() + " has " + std::to_string(gtCount));
	}
	for (const auto &[imId, gts] : gt)
		if (!gts.empty() && !info.count(imId))
			return makeError(Errc::kCorrupt,
					 infoFile.string() + ": no entry for image " +
						 std::to_string(imId) + " which " + gtFile.string() +
						 " has");
	return {};
}

} // namespace

Expected<BopDataset> BopDataset::open(const fs::path &root, const std::string &split)
{
	std::error_code ec;
	if (!fs::is_directory(root, ec))
		return makeError(Errc::kNotFound, root.string() + ": dataset folder not found");

	BopDataset ds;
	ds.root_ = root;

	auto camera = readBopCamera(root / "camera.json");
	if (!camera)
		return camera.error();
	ds.camera_ = *camera;

	const fs::path infoFile = root / "models" / "models_info.json";
	if (fs::exists(infoFile, ec)) {
		auto info = readModelsInfo(infoFile);
		if (!info)
			return info.error();
		ds.modelsInfo_ = std::move(*info);
	}

	if (!split.empty()) {
		if (!fs::is_directory(root / split, ec))
			return makeError(Errc::kNotFound,
					 (root / split).string() + ": split folder not found");
		ds.split_ = split;
	} else {
		ds.split_ = "test";
		for (const char *name : {"test", "val", "train"}) {
			if (fs::is_directory(root / name, ec)) {
				ds.split_ = name;
				break;
			}
		}
	}
	return ds;
}

std::vector<int> BopDataset::sceneIds() const
{
	std::vector<int> ids;
	std::error_code ec;
	for (fs::directory_iterator it(root_ / split_, ec), end; !ec && it != end; it.increment(ec)) {
		std::string name = it->path().filename().string();
		if (isSixDigits(name) && it->is_directory(ec))
			ids.push_back(std::stoi(name));
	}
	std::sort(ids.begin(), ids.end());
	return ids;
}

fs::path BopDataset::sceneDir(int sceneId) const
{
	return root_ / split_ / sixDigits(sceneId);
}

fs::path BopDataset::depthPath(int sceneId, int imId) const
{
	return sceneDir(sceneId) / "depth" / (sixDigits(imId) + ".png");
}

fs::path BopDataset::modelPath(int objId) const
{
	return root_ / "models" / ("obj_" + sixDigits(objId) + ".ply");
}

std::optional<int> modelObjId(std::string_view stem)
{
	constexpr std::string_view prefix = "obj_";
	if (!stem.starts_with(prefix) || stem.size() == prefix.size())
		return std::nullopt;
	const char *first = stem.data() + prefix.size(), *last = stem.data() + stem.size();
	int id = 0;
	const auto [end, ec] = std::from_chars(first, last, id);
	// Digits only: from_chars would take a sign.
	if (ec != std::errc() || end != last || *first < '0' || *first > '9')
		return std::nullopt;
	return id;
}

Expected<BopScene> BopDataset::loadScene(int sceneId) const
{
	auto scene = loadSceneCameras(sceneId);
	if (!scene)
		return scene;
	if (Status s = loadSceneGt(*scene); !s)
		return s.error();
	return scene;
}

Expected<BopScene> BopDataset::loadSceneCameras(int sceneId) const
{
	const fs::path dir = sceneDir(sceneId);
	std::error_code ec;
	if (!fs::is_directory(dir, ec))
		return makeError(Errc::kNotFound, dir.string() + ": scene folder not found");

	BopScene scene;
	scene.sceneId = sceneId;
	auto cams = readSceneCamera(dir / "scene_camera.json");
	if (!cams)
		return cams.error();
	scene.cameras = std::move(*cams);
	for (auto &[imId, cam] : scene.cameras) {
		cam.intrinsics.width = camera_.intrinsics.width;
		cam.intrinsics.height = camera_.intrinsics.height;
	}
	return scene;
}

Status BopDataset::loadSceneGt(BopScene &scene) const
{
	const fs::path dir = sceneDir(scene.sceneId);
	const fs::path camFile = dir / "scene_camera.json";
	const fs::path gtFile = dir / "scene_gt.json";
	auto gt = readSceneGt(gtFile);
	if (!gt)
		return gt.error();
	for (const auto &[imId, instances] : *gt)
		if (!scene.cameras.count(imId))
			return makeError(Errc::kCorrupt, gtFile.string() + ": \"" + std::to_string(imId) +
								 "\": image has no entry in " +
								 camFile.string());

	std::map<int, std::vector<GtInfo>> info;
	const fs::path infoFile = dir / "scene_gt_info.json";
	std::error_code ec;
	if (fs::exists(infoFile, ec)) {
		auto read = readSceneGtInfo(infoFile);
		if (!read)
			return read.error();
		if (Status s = checkGtInfoMatches(*gt, *read, gtFile, infoFile); !s)
			return s;
		info = std::move(*read);
	}
	scene.gt = std::move(*gt);
	scene.gtInfo = std::move(info);
	return {};
}

Status BopDataset::saveScene(const BopScene &scene) const
{
	const fs::path dir = sceneDir(scene.sceneId);
	if (!scene.gtInfo.empty())
		if (Status s = checkGtInfoMatches(scene.gt, scene.gtInfo, dir / "scene_gt.json",
						  dir / "scene_gt_info.json"); !s)
			return s;
	if (Status s = writeSceneCamera(dir / "scene_camera.json", scene.cameras); !s)
		return s;
	if (Status s = writeSceneGt(dir / "scene_gt.json", scene.gt); !s)
		return s;
	if (!scene.gtInfo.empty())
		return writeSceneGtInfo(dir / "scene_gt_info.json", scene.gtInfo);
	return {};
}

Expected<DepthImageMm> BopDataset::loadDepthMm(int sceneId, int imId, double depthScale) const
{
	const fs::path path = depthPath(sceneId, imId);
	if (!(depthScale > 0))
		return makeError(Errc::kInvalidArgument, path.string() + ": depth scale " +
								 std::to_string(depthScale) + " is not positive");
	auto raw = readDepthPng(path);
	if (!raw)
		return raw.error();

	DepthImageMm mm(raw->width(), raw->height());
	auto src = raw->pixels();
	auto dst = mm.pixels();
	for (size_t i = 0; i < src.size(); ++i)
		dst[i] = static_cast<float>(src[i] * depthScale);
	return mm;
}

Expected<Mesh> BopDataset::loadModel(int objId) const
{
	const fs::path path = modelPath(objId);
	std::error_code ec;
	if (!fs::exists(path, ec))
		return makeError(Errc::kNotFound, path.string() + ": model of object " +
							  std::to_string(objId) + " not found");
	return loadPly(path);
}

Status createBopDataset(const fs::path &root, const BopCamera &camera,
			const std::map<int, ModelInfo> &modelsInfo)
{
	if (Status s = writeBopCamera(root / "camera.json", camera); !s)
		return s;
	return writeModelsInfo(root / "models" / "models_info.json", modelsInfo);
}

} // namespace ihf
