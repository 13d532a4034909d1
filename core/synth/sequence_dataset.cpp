// SPDX-License-Identifier: MIT
#include "core/synth/sequence_dataset.h"

#include <chrono>
#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "core/dataset/atomic_file.h"
#include "core/dataset/bop_io.h"
#include "core/synth/dataset_staging.h"
#include "core/synth/model_library.h"
#include "core/synth/sequence_synthesizer.h"

namespace ihf {

namespace fs = std::filesystem;

namespace {

const char *carryName(CarryKind kind)
{
	switch (kind) {
	case CarryKind::kMove:
		return "move";
	case CarryKind::kTakeAway:
		return "take_away";
	case CarryKind::kPutDown:
		return "put_down";
	}
	return "?";
}

// Seconds to the millisecond (the nearest double to the decimal).
double millis(double v) { return std::round(v * 1000.0) / 1000.0; }

nlohmann::ordered_json describeScene(const SequenceScene &scene, double fps)
{
	nlohmann::ordered_json j;
	j["scene_id"] = scene.sequenceId;
	j["motion"] = cameraMotionName(scene.path.style());
	j["duration_s"] = millis(scene.path.duration());
	std::vector<int> targets;
	for (const TargetSlot &t : scene.targets)
		targets.push_back(t.objId);
	j["targets"] = targets;
	nlohmann::ordered_json events = nlohmann::ordered_json::array();
	for (const TargetSlot &t : scene.targets) {
		for (const Carry &c : t.schedule.carries()) {
			nlohmann::ordered_json e;
			e["kind"] = carryName(c.kind);
			e["obj_id"] = t.objId;
			e["start_frame"] = static_cast<int>(std::ceil(c.start * fps));
			e["end_frame"] = static_cast<int>(std::ceil(c.end * fps));
			e["start_s"] = millis(c.start);
			e["end_s"] = millis(c.end);
			events.push_back(e);
		}
	}
	j["events"] = events;
	nlohmann::ordered_json pauses = nlohmann::ordered_json::array();
	for (const PathPause &p : scene.path.pauses())
		pauses.push_back({millis(p.start), millis(p.end)});
	j["pauses_s"] = pauses;
	j["quick_turns"] = scene.path.quickTurns();
	return j;
}

std::string configRecord(const SequenceConfig &c, const CameraIntrinsics &K)
{
	const SequenceParams &p = c.params;
	nlohmann::ordered_json j;
	j["generator"] = "ihf synth --sequence 0.1.0";
	j["models"] = c.modelsDir.string();
	j["objects"] = c.objects;
	j["sequences"] = c.sequences;
	j["frames"] = p.frames;
	j["fps"] = p.fps;
	j["seed"] = p.synth.seed;
	j["per_frame"] = {p.perFrameMin, p.perFrameMax};
	j["motion"] = cameraMotionName(p.motion);
	j["max_speed_mm_s"] = p.path.maxSpeedMmS;
	j["max_turn_deg_s"] = p.path.maxTurnDegS;
	j["distance_mm"] = {p.path.distanceMin, p.path.distanceMax};
	j["elevation_deg"] = {p.path.elevationMinDeg, p.path.elevationMaxDeg};
	j["clutter"] = {p.synth.layout.clutterMin, p.synth.layout.clutterMax};
	j["wall_probability"] = p.synth.layout.wallProbability;
	j["change_probability"] = p.changeProbability;
	j["miss_probability"] = p.detector.missProbability;
	j["min_visib_fract"] = p.detector.minVisibFract;
	j["sensor"] = p.synth.model == SensorModel::kKinect ? "kinect-v1" : sensorModelName(p.synth.model);
	j["depth_scale"] = p.synth.depthScale;
	j["cam_K"] = {K.fx, 0.0, K.cx, 0.0, K.fy, K.cy, 0.0, 0.0, 1.0};
	return j.dump(1) + "\n";
}

} // namespace

Expected<SequenceSummary> runSynthSequences(const SequenceConfig &config,
					    const SequenceProgress &progress,
					    const SequenceSceneHook &sceneHook)
{
	const auto start = std::chrono::steady_clock::now();
	if (Status valid = validateSequenceConfig(config); !valid)
		return valid.error();
	auto cameraOr = synthCamera(config.cameraFile, config.params.synth.depthScale);
	if (!cameraOr)
		return cameraOr.error();
	const BopCamera camera = *cameraOr;
	const CameraIntrinsics &K = camera.intrinsics;
	const fs::path out = config.outDir;
	if (Status st = checkOutputFree(out, config.overwrite); !st)
		return st.error();
	auto library = ModelLibrary::load(config.modelsDir, config.objects);
	if (!library)
		return library.error();
	auto staged = StagingFolder::create(out);
	if (!staged)
		return staged.error();
	const fs::path root = staged->dir();
	if (Status st = staged->addModels(*library, config.objects, camera); !st)
		return st.error();

	SequenceSynthesizer synth(*library, K, config.params, config.objects);
	SequenceSummary summary;
	std::vector<Detection> detections;
	nlohmann::ordered_json described = nlohmann::ordered_json::array();
	const int frames = config.params.frames;
	std::error_code ec;
	for (int seq = 1; seq <= config.sequences; ++seq) {
		const auto seqStart = std::chrono::steady_clock::now();
		auto scene = synth.plan(seq);
		if (!scene)
			return scene.error();
		described.push_back(describeScene(*scene, config.params.fps));
		const fs::path sceneDir = root / "test" / sixDigits(seq);
		fs::create_directories(sceneDir / "depth", ec);
		if (ec)
			return makeError(Errc::kIo, sceneDir.string() + ": " + ec.message());
		std::map<int, SceneCamera> cams;
		std::map<int, std::vector<GtInstance>> gts;
		std::map<int, std::vector<GtInfo>> infos;
		for (int f = 0; f < frames; ++f) {
			auto frame = synth.frame(*scene, f);
			if (!frame)
				return frame.error();
			if (Status st = writeDepthPng(sceneDir / "depth" / (sixDigits(f) + ".png"), frame->depth); !st)
				return st.error();
			cams[f] = SceneCamera{K, camera.depthScale};
			gts[f] = frame->gt;
			infos[f] = frame->info;
			summary.instances += static_cast<int>(frame->gt.size());
			summary.boxes += static_cast<int>(frame->detections.size());
			detections.insert(detections.end(), frame->detections.begin(), frame->detections.end());
			++summary.frames;
			if (progress)
				progress(seq, f, frames);
		}
		Status st = writeSceneCamera(sceneDir / "scene_camera.json", cams);
		if (st)
			st = writeSceneGt(sceneDir / "scene_gt.json", gts);
		if (st)
			st = writeSceneGtInfo(sceneDir / "scene_gt_info.json", infos);
		if (!st)
			return st.error();
		++summary.sequences;
		summary.secondsPerSequence.push_back(
			std::chrono::duration<double>(std::chrono::steady_clock::now() - seqStart).count());
	}
	Status st = writeDetections(root / "boxes.json", detections);
	if (st)
		st = writeFileAtomic(root / "sequences.json", described.dump(1) + "\n");
	if (st)
		st = writeFileAtomic(root / "synth_config.json", configRecord(config, K));
	if (!st)
		return st.error();
	if (sceneHook) {
		for (int seq = 1; seq <= config.sequences; ++seq)
			if (Status s = sceneHook(root, seq); !s)
				return s.error();
	}
	if (Status s = staged->commit(out); !s)
		return s.error();
	summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
	return summary;
}

} // namespace ihf
