// SPDX-License-Identifier: MIT
#include "core/synth/scene_synthesizer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/synth/gt_info_builder.h"
#include "core/synth/projector_shadow.h"

namespace ihf {

const char *sensorModelName(SensorModel model)
{
	switch (model) {
	case SensorModel::kKinect:
		return "kinect";
	case SensorModel::kTof:
		return "tof";
	case SensorModel::kIdeal:
		return "ideal";
	}
	return "?";
}

std::optional<SensorModel> sensorModelNamed(std::string_view name)
{
	for (SensorModel m : {SensorModel::kKinect, SensorModel::kTof, SensorModel::kIdeal})
		if (name == sensorModelName(m))
			return m;
	return std::nullopt;
}

DepthImage16 sensorDepth(const SynthParams &params, const SceneLayout &layout,
			 const CameraIntrinsics &K, ImageView<const float> depth,
			 ImageView<const uint16_t> label, ImageView<const float> projector,
			 int projectorPad, SynthRandom &rng)
{
	if (params.model == SensorModel::kIdeal) {
		DepthImage16 out(K.width, K.height, 0);
		for (int y = 0; y < K.height; ++y)
			for (int x = 0; x < K.width; ++x)
				out.at(x, y) = static_cast<uint16_t>(
					std::min(std::round(depth.at(x, y) / params.depthScale), 65535.0));
		return out;
	}
	SensorScene scene;
	scene.depth = depth;
	scene.label = label;
	scene.projector = projector;
	scene.projectorX0 = -projectorPad;
	scene.labelDropout.assign(layout.objects.size() + 1, 0.0f);
	for (size_t i = 0; i < layout.objects.size(); ++i)
		scene.labelDropout[sceneLabel(i)] = static_cast<float>(layout.objects[i].dropout);
	return params.model == SensorModel::kTof
		       ? simulateTof(scene, K, params.tof, rng, params.depthScale)
		       : simulateKinect(scene, K, params.sensor, rng, params.depthScale);
}

SceneSynthesizer::SceneSynthesizer(const ModelLibrary &library, const CameraIntrinsics &K,
				   SynthParams params)
	: K_(K), params_(params),
	  renderer_(K, std::max<size_t>(library.maxVertices(), 4096)),
	  sampler_(library, K, params.layout)
{
	// Projector buffer reaches left of the image by the largest shift,
	// fx b / z at the sensor's minimum range (nearer points are dropped).
	projectorPad_ = projectorPadding(K_, params_.sensor.baselineMm,
					 0.8 * params_.sensor.minRangeMm);
	depth_ = DepthImageMm(K_.width, K_.height);
	label_ = Image<uint16_t>(K_.width, K_.height);
	projector_ = DepthImageMm(K_.width + projectorPad_, K_.height);
}

Expected<SynthImage> SceneSynthesizer::synthesize(int objId, int imageId)
{
	Error last = makeError(Errc::kOutOfRange, "");
	const uint64_t imageKey = mixSeed(mixSeed(params_.seed, static_cast<uint64_t>(objId)),
					  static_cast<uint64_t>(imageId));
	// The occlusion goal is the image's, kept over the attempts so that
	// failures do not skew the achieved occlusions towards easy values.
	SynthRandom goalRng(mixSeed(imageKey, 0x6f63636c));
	const double goal = goalRng.uniform(params_.occlusionMin, params_.occlusionMax);
	for (int a = 0; a < params_.maxAttempts; ++a) {
		SynthRandom rng(mixSeed(imageKey, static_cast<uint64_t>(a)));
		auto img = attempt(objId, imageId, a, goal, rng);
		if (img) {
			img->attempts = a + 1;
			return img;
		}
		if (img.error().code != Errc::kOutOfRange)
			return img.error();
		last = img.error();
	}
	return makeError(Errc::kOutOfRange,
			 "synth: object " + std::to_string(objId) + " image " +
				 std::to_string(imageId) + ": no scene met the occlusion range after " +
				 std::to_string(params_.maxAttempts) + " attempts (" + last.message + ")");
}

Expected<SynthImage> SceneSynthesizer::attempt(int objId, int imageId, int index,
					       double goalValue, SynthRandom &rng)
{
	// Steep views cannot be occluded by things standing on the table (they
	// would have to reach up to the camera): after a failure, lower the
	// highest elevation step by step.
	const LayoutParams &lp = params_.layout;
	const double half = std::max(1, params_.maxAttempts / 2);
	const double cap = lp.elevationMaxDeg - 0.75 * (lp.elevationMaxDeg - lp.elevationMinDeg) *
							std::min(1.0, index / half);
	SceneLayout layout = sampler_.sampleBase(objId, rng, cap);
	sampler_.addClutter(layout, objId, rng);

	OcclusionGoal goal;
	goal.min = params_.occlusionMin;
	goal.max = params_.occlusionMax;
	goal.goal = goalValue;
	goal.tolerance = params_.occlusionTolerance;
	goal.truncationProbability = params_.truncationProbability;
	OcclusionController controller(sampler_, renderer_);
	auto outcome = controller.apply(layout, goal, rng);
	if (!outcome)
		return outcome.error();
	// Give up early (before the costly renders) when the control missed.
	const bool strict = index < params_.maxAttempts / 2;
	if (outcome->occlusion < params_.occlusionMin - 0.01 ||
	    outcome->occlusion > params_.occlusionMax + 0.01 ||
	    (strict && std::abs(outcome->occlusion - goal.goal) > params_.goalSlack))
		return makeError(Errc::kOutOfRange, "occlusion control missed its goal");
	sampler_.addRoom(layout, rng);

	// Camera and projector views of the whole scene.
	const Pose &view = layout.view.worldToCamera;
	Status st = renderer_.renderScene(layout, view, depth_.view(), label_.view());
	if (!st)
		return st.error();
	if (params_.model == SensorModel::kKinect) {
		st = renderer_.renderScene(layout, SceneRenderer::projectorView(view, params_.sensor.baselineMm),
					   projector_.view(), {}, RenderWindow{-projectorPad_, 0});
		if (!st)
			return st.error();
	}
	auto sil = renderer_.silhouette(layout.objects[0], view);
	if (!sil)
		return sil.error();

	// The occlusion as BOP measures it, from the final render.
	int visible = 0;
	for (uint16_t l : label_.pixels())
		visible += l == sceneLabel(0) ? 1 : 0;
	const double occlusion = sil->pxCountAll > 0 ? 1.0 - static_cast<double>(visible) / sil->pxCountAll : 1.0;
	if (visible == 0 || occlusion < params_.occlusionMin - 1e-12 ||
	    occlusion > params_.occlusionMax + 1e-12 ||
	    (strict && std::abs(occlusion - goal.goal) > params_.goalSlack)) {
		char msg[96];
		std::snprintf(msg, sizeof(msg), "occlusion %.3f, goal %.3f in [%.3f, %.3f]", occlusion,
			      goal.goal, params_.occlusionMin, params_.occlusionMax);
		return makeError(Errc::kOutOfRange, std::string(msg));
	}

	SynthImage img;
	img.depth = sensorDepth(params_, layout, K_, depth_.view(), label_.view(), projector_.view(),
				projectorPad_, rng);

	img.gt.objId = objId;
	img.gt.pose = view * layout.objects[0].modelToWorld;
	img.info = buildGtInfo(*sil, label_.view(), sceneLabel(0), img.depth);
	img.detection = coarseDetection(img.info.bboxObj, K_.width, K_.height, objId, imageId, objId,
					rng, params_.detection);
	img.occlusionGoal = goal.goal;
	img.outcome = *outcome;
	int others = 0;
	for (const SceneObject &o : layout.objects)
		others += (o.role != SceneRole::kTarget && o.role != SceneRole::kRoom) ? 1 : 0;
	img.objects = others;
	if (params_.keepClean) {
		img.cleanDepth = depth_;
		img.cleanLabel = label_;
		img.layout = layout;
	}
	return img;
}

} // namespace ihf
