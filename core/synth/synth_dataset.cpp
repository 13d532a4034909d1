// SPDX-License-Identifier: MIT
#include "core/synth/synth_dataset.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/bop_io.h"
#include "core/synth/dataset_staging.h"
#include "core/synth/depth_colormap.h"
#include "core/synth/model_library.h"

namespace ihf {

namespace fs = std::filesystem;

namespace {

Status writeConfigRecord(const fs::path &file, const SynthConfig &c, const CameraIntrinsics &K)
{
	const SynthParams &p = c.params;
	nlohmann::ordered_json j;
	j["generator"] = "ihf synth 0.1.0";
	j["models"] = c.modelsDir.string();
	j["objects"] = c.objects;
	j["images_per_object"] = c.images;
	j["seed"] = p.seed;
	j["distance_mm"] = {p.layout.distanceMin, p.layout.distanceMax};
	j["occlusion"] = {p.occlusionMin, p.occlusionMax};
	j["elevation_deg"] = {p.layout.elevationMinDeg, p.layout.elevationMaxDeg};
	j["clutter"] = {p.layout.clutterMin, p.layout.clutterMax};
	j["wall_probability"] = p.layout.wallProbability;
	j["sensor"] = p.model == SensorModel::kKinect ? "kinect-v1" : sensorModelName(p.model);
	j["depth_scale"] = p.depthScale;
	j["cam_K"] = {K.fx, 0.0, K.cx, 0.0, K.fy, K.cy, 0.0, 0.0, 1.0};
	const std::string text = j.dump(1) + "\n";
	const fs::path tmp = file.string() + ".tmp";
	{
		std::ofstream out(tmp, std::ios::binary);
		out << text;
		if (!out)
			return makeError(Errc::kIo, tmp.string() + ": cannot write");
	}
	std::error_code ec;
	fs::rename(tmp, file, ec);
	if (ec)
		return makeError(Errc::kIo, file.string() + ": " + ec.message());
	return {};
}

} // namespace

Expected<SynthSummary> runSynth(const SynthConfig &config, const SynthProgress &progress)
{
	const auto start = std::chrono::steady_clock::now();
	Status valid = validateConfig(config);
	if (!valid)
		return valid.error();

	auto cameraOr = synthCamera(config.cameraFile, config.params.depthScale);
	if (!cameraOr)
		return cameraOr.error();
	const BopCamera camera = *cameraOr;
	const CameraIntrinsics &K = camera.intrinsics;

	const fs::path out = config.outDir;
	Status st = checkOutputFree(out, config.overwrite);
	if (!st)
		return st.error();

	auto library = ModelLibrary::load(config.modelsDir, config.objects);
	if (!library)
		return library.error();

	auto staged = StagingFolder::create(out);
	if (!staged)
		return staged.error();
	const fs::path staging = staged->dir();
	std::error_code ec;
	st = staged->addModels(*library, config.objects, camera);
	if (!st)
		return st.error();

	SceneSynthesizer synth(*library, K, config.params);
	SynthSummary summary;
	std::vector<Detection> detections;
	std::map<std::pair<int, int>, std::pair<DepthImage16, double>> previews;
	const int total = config.images * static_cast<int>(config.objects.size());
	int done = 0;
	for (int objId : config.objects) {
		const fs::path sceneDir = staging / "test" / sixDigits(objId);
		fs::create_directories(sceneDir / "depth", ec);
		if (ec)
			return makeError(Errc::kIo, sceneDir.string() + ": " + ec.message());
		std::map<int, SceneCamera> cams;
		std::map<int, std::vector<GtInstance>> gts;
		std::map<int, std::vector<GtInfo>> infos;
		for (int im = 0; im < config.images; ++im) {
			auto img = synth.synthesize(objId, im);
			if (!img)
				return img.error();
			st = writeDepthPng(sceneDir / "depth" / (sixDigits(im) + ".png"), img->depth);
			if (!st)
				return st.error();
			cams[im] = SceneCamera{K, camera.depthScale};
			gts[im] = {img->gt};
			infos[im] = {img->info};
			detections.push_back(img->detection);
			summary.occlusion.push_back(1.0 - img->info.visibFract);
			summary.objectOf.push_back(objId);
			summary.attemptsTotal += img->attempts;
			summary.occludersTotal += img->outcome.occluders;
			summary.truncated += img->outcome.truncation > 0.01 ? 1 : 0;
			if (!config.previewDir.empty() && im < config.previewCount)
				previews[{objId, im}] = {img->depth, img->gt.pose.t.z()};
			++done;
			if (progress)
				progress(objId, im, done, total, *img);
		}
		st = writeSceneCamera(sceneDir / "scene_camera.json", cams);
		if (st)
			st = writeSceneGt(sceneDir / "scene_gt.json", gts);
		if (st)
			st = writeSceneGtInfo(sceneDir / "scene_gt_info.json", infos);
		if (!st)
			return st.error();
	}
	st = writeDetections(staging / "boxes.json", detections);
	if (st)
		st = writeConfigRecord(staging / "synth_config.json", config, K);
	if (!st)
		return st.error();

	// Move the finished set into place.
	st = staged->commit(out);
	if (!st)
		return st.error();

	if (!config.previewDir.empty()) {
		fs::create_directories(config.previewDir, ec);
		for (const auto &[key, shot] : previews) {
			const fs::path file = config.previewDir /
					      ("obj_" + sixDigits(key.first) + "_" + sixDigits(key.second) + ".png");
			// Colours from 35 cm before to 65 cm behind the target.
			st = writeDepthPicture(file, shot.first, camera.depthScale, shot.second - 350.0,
					       shot.second + 650.0);
			if (!st)
				return st.error();
		}
	}
	summary.images = done;
	summary.seconds =
		std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
	return summary;
}

} // namespace ihf
