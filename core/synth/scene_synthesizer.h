// SPDX-License-Identifier: MIT
#pragma once

// One synthetic test image of one target: lays out a tabletop scene, drives
// the target's occlusion into the requested range, renders it from the
// camera and the projector, passes it through the Kinect model and derives
// the ground truth (pose, scene_gt_info entry, coarse detection box). Every
// image draws from its own random stream, seeded from (seed, object, image,
// attempt), so images do not depend on each other or on the object order.

#include <optional>
#include <string_view>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/dataset/bop_types.h"
#include "core/synth/detection_box.h"
#include "core/synth/kinect_sensor.h"
#include "core/synth/model_library.h"
#include "core/synth/occlusion_control.h"
#include "core/synth/scene_layout.h"
#include "core/synth/scene_render.h"
#include "core/synth/tof_sensor.h"

namespace ihf {

enum class SensorModel {
	kKinect, // structured light (kinect_sensor.h)
	kTof,    // continuous-wave time of flight (tof_sensor.h)
	kIdeal,  // clean depth, only rounded to depthScale
};

// The name `ihf synth --sensor` takes and the dataset records, and the
// model of a name (nullopt: none).
const char *sensorModelName(SensorModel model);
std::optional<SensorModel> sensorModelNamed(std::string_view name);

struct SynthParams {
	LayoutParams layout;
	SensorModel model = SensorModel::kKinect;
	KinectParams sensor; // the Kinect model's parameters
	TofParams tof;       // the time-of-flight model's parameters
	DetectionNoise detection;
	double occlusionMin = 0.0, occlusionMax = 0.6;
	double occlusionTolerance = 0.03;
	double truncationProbability = 0.1;
	double depthScale = 1.0; // raw * depthScale = mm
	uint64_t seed = 0;
	int maxAttempts = 16;
	// The first attempts must also land within this of their sampled goal,
	// so that failed occluder searches do not pile images up at low occlusion.
	double goalSlack = 0.05;
	bool keepClean = false; // keep the clean render in SynthImage (tests)
};

struct SynthImage {
	DepthImage16 depth;          // sensor depth, raw units of depthScale
	GtInstance gt;
	GtInfo info;
	Detection detection;
	double occlusionGoal = 0;
	OcclusionOutcome outcome;
	int attempts = 0;
	int objects = 0;             // objects in the scene besides the target
	// Only with keepClean: clean depth (mm) and labels (target = 1).
	DepthImageMm cleanDepth;
	Image<uint16_t> cleanLabel;
	SceneLayout layout;
};

// The sensor's depth of a rendered scene (depth and labels from the camera,
// projector depth from the projector with projectorPad columns left of the
// image, used by the Kinect model only), in units of params.depthScale.
DepthImage16 sensorDepth(const SynthParams &params, const SceneLayout &layout,
			 const CameraIntrinsics &K, ImageView<const float> depth,
			 ImageView<const uint16_t> label, ImageView<const float> projector,
			 int projectorPad, SynthRandom &rng);

class SceneSynthesizer
{
public:
	SceneSynthesizer(const ModelLibrary &library, const CameraIntrinsics &K, SynthParams params);

	Expected<SynthImage> synthesize(int objId, int imageId);

	const SynthParams &params() const { return params_; }

private:
	Expected<SynthImage> attempt(int objId, int imageId, int index, double goal,
				     SynthRandom &rng);

	CameraIntrinsics K_;
	SynthParams params_;
	SceneRenderer renderer_;
	LayoutSampler sampler_;
	int projectorPad_ = 0;
	DepthImageMm depth_;
	Image<uint16_t> label_;
	DepthImageMm projector_;
};

} // namespace ihf
