// SPDX-License-Identifier: MIT
#include "core/eval/run_pose_check.h"

#include <cmath>
#include <limits>
#include <set>

#include "core/dataset/bop_frames.h"
#include "core/eval/eval_dataset.h"

namespace ihf {

namespace {

std::vector<Pose> truthsOf(const BopScene &scene, int imageId, int objId)
{
	std::vector<Pose> truths;
	auto it = scene.gt.find(imageId);
	if (it == scene.gt.end())
		return truths;
	for (const GtInstance &instance : it->second)
		if (instance.objId == objId)
			truths.push_back(instance.pose);
	return truths;
}

std::string imagesOf(const BopScene &scene)
{
	if (scene.cameras.empty())
		return "no images";
	return std::to_string(scene.cameras.size()) + " images, ids " +
	       std::to_string(scene.cameras.begin()->first) + ".." +
	       std::to_string(scene.cameras.rbegin()->first);
}

// A line placed in the scene: the image its frame was recorded from and
// the instances of its object there (`truths`, empty when there is nothing
// to compare: then "no pose" or "no truth" with why).
RunPoseCheck place(const BopScene &scene, const RunPoseLine &line, const RunPoseRequest &request,
		   std::vector<Pose> &truths)
{
	RunPoseCheck check;
	check.line = line.line;
	check.frame = line.frame;
	check.objId = line.objId;
	if (line.frame) {
		if (const std::optional<int> image = recordedImageOf(scene, *line.frame)) {
			check.sceneId = scene.sceneId;
			check.imageId = *image;
		}
	}
	if (!line.pose) {
		check.verdict = RunPoseVerdict::kNoPose;
		check.note = line.error;
		return check;
	}
	const std::string where = request.posesFile.string() + " line " + std::to_string(line.line) + ": ";
	check.verdict = RunPoseVerdict::kNoTruth;
	if (check.imageId < 0) {
		check.note = where + "frame " + std::to_string(*line.frame) + " was not recorded from scene " +
			     std::to_string(scene.sceneId) + " (" + imagesOf(scene) + ")";
		return check;
	}
	truths = truthsOf(scene, check.imageId, *line.objId);
	if (truths.empty())
		check.note = where + "object " + std::to_string(*line.objId) + " has no ground truth in image " +
			     std::to_string(check.imageId) + " of scene " + std::to_string(scene.sceneId);
	return check;
}

} // namespace

void comparePose(const Pose &estimate, std::span<const Pose> truths, const EvalObject &object,
		 double threshold, RunPoseCheck &check)
{
	const ObjectPoseError &error = *object.error;
	double best = std::numeric_limits<double>::infinity();
	const Pose *closest = &truths.front();
	for (const Pose &truth : truths) {
		const double e = error(estimate, truth);
		if (e < best) {
			best = e;
			closest = &truth;
		}
	}
	check.metric = error.metric();
	check.errorMm = best;
	check.errorShare = best / object.diameter;
	check.rotationDeg = rotationAngle(estimate.R, closest->R) * 180.0 / M_PI;
	check.translationMm = (estimate.t - closest->t).norm();
	check.verdict = best <= threshold * object.diameter ? RunPoseVerdict::kRight : RunPoseVerdict::kWrong;
}

Expected<RunPoseReport> checkRunPoses(const BopDataset &dataset, const std::vector<RunPoseLine> &lines,
				      const RunPoseRequest &request)
{
	Expected<int> sceneId = recordedSceneId(dataset, request.sceneId);
	if (!sceneId)
		return sceneId.error();
	Expected<BopScene> scene = dataset.loadScene(*sceneId);
	if (!scene)
		return scene.error();

	RunPoseReport report;
	report.sceneId = *sceneId;
	report.threshold = request.threshold;
	std::vector<std::vector<Pose>> truths(lines.size());
	std::set<int> objectIds;
	for (size_t i = 0; i < lines.size(); ++i) {
		report.checks.push_back(place(*scene, lines[i], request, truths[i]));
		if (!truths[i].empty())
			objectIds.insert(*lines[i].objId);
	}

	Expected<EvalModels> models = loadEvalModels(dataset, objectIds);
	if (!models)
		return models.error();
	for (size_t i = 0; i < lines.size(); ++i)
		if (!truths[i].empty())
			comparePose(*lines[i].pose, truths[i], models->objects.at(*lines[i].objId),
				    request.threshold, report.checks[i]);
	return report;
}

} // namespace ihf
