// SPDX-License-Identifier: MIT
#include "core/synth/sequence_synthesizer.h"

#include <algorithm>
#include <numeric>

#include "core/synth/gt_info_builder.h"
#include "core/synth/projector_shadow.h"
#include "core/synth/scene_synthesizer.h"

namespace ihf {

namespace {

constexpr uint64_t kFrameTag = 0x6672616d65ull; // "frame"

} // namespace

SequenceSynthesizer::SequenceSynthesizer(const ModelLibrary &library, const CameraIntrinsics &K,
					 SequenceParams params, std::vector<int> objects)
	: library_(library), K_(K), params_(std::move(params)), objects_(std::move(objects)),
	  renderer_(K, std::max<size_t>(library.maxVertices(), 4096))
{
	projectorPad_ = projectorPadding(K_, params_.synth.sensor.baselineMm,
					 0.8 * params_.synth.sensor.minRangeMm);
	depth_ = DepthImageMm(K_.width, K_.height);
	label_ = Image<uint16_t>(K_.width, K_.height);
	projector_ = DepthImageMm(K_.width + projectorPad_, K_.height);
}

Expected<SequenceScene> SequenceSynthesizer::plan(int sequenceId) const
{
	return planSequenceScene(library_, K_, params_, objects_, sequenceId);
}

Expected<SequenceFrame> SequenceSynthesizer::frame(const SequenceScene &scene, int frameIndex)
{
	const double t = frameIndex / params_.fps;
	SynthRandom rng(mixSeed(mixSeed(scene.key, kFrameTag), static_cast<uint64_t>(frameIndex)));

	// The scene at t: the targets present, where their schedules put them,
	// then everything that stands still.
	SceneLayout layout;
	std::vector<size_t> slotOf; // layout index -> target slot
	for (size_t s = 0; s < scene.targets.size(); ++s) {
		const ObjectSchedule &schedule = scene.targets[s].schedule;
		if (!schedule.present(t))
			continue;
		SceneObject obj = scene.layout.objects[s];
		obj.modelToWorld = schedule.modelToWorld(t);
		layout.objects.push_back(obj);
		slotOf.push_back(s);
	}
	const size_t targets = layout.objects.size();
	for (size_t i = scene.targets.size(); i < scene.layout.objects.size(); ++i)
		layout.objects.push_back(scene.layout.objects[i]);

	SequenceFrame out;
	out.worldToCamera = scene.path.worldToCamera(t);
	const Pose &view = out.worldToCamera;
	Status st = renderer_.renderScene(layout, view, depth_.view(), label_.view());
	if (!st)
		return st.error();
	if (params_.synth.model == SensorModel::kKinect) {
		st = renderer_.renderScene(layout,
					   SceneRenderer::projectorView(view, params_.synth.sensor.baselineMm),
					   projector_.view(), {}, RenderWindow{-projectorPad_, 0});
		if (!st)
			return st.error();
	}
	out.depth = sensorDepth(params_.synth, layout, K_, depth_.view(), label_.view(),
				projector_.view(), projectorPad_, rng);

	// Ground truth of the visible targets, by object id.
	std::vector<int> visible(targets + 1, 0);
	for (uint16_t l : label_.pixels())
		if (l >= 1 && l <= targets)
			++visible[l - 1];
	std::vector<size_t> order(targets);
	std::iota(order.begin(), order.end(), size_t{0});
	std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
		return scene.targets[slotOf[a]].objId < scene.targets[slotOf[b]].objId;
	});
	for (size_t i : order) {
		if (visible[i] == 0)
			continue;
		auto sil = renderer_.silhouette(layout.objects[i], view);
		if (!sil && sil.error().code == Errc::kOutOfRange)
			continue; // reaches behind the lens: nearer than any sensor sees
		if (!sil)
			return sil.error();
		const TargetSlot &slot = scene.targets[slotOf[i]];
		GtInstance gt;
		gt.objId = slot.objId;
		gt.pose = view * layout.objects[i].modelToWorld;
		out.gt.push_back(gt);
		out.info.push_back(buildGtInfo(*sil, label_.view(), sceneLabel(i), out.depth));
		out.gtLabel.push_back(sceneLabel(i));
	}
	for (size_t k = 0; k < out.gt.size(); ++k) {
		const size_t slot = slotOf[out.gtLabel[k] - 1];
		const bool missed = scene.targets[slot].misses[static_cast<size_t>(frameIndex)] != 0;
		auto det = detectObject(out.info[k], missed, K_.width, K_.height, scene.sequenceId,
					frameIndex, out.gt[k].objId, rng, params_.detector);
		if (det)
			out.detections.push_back(*det);
	}
	if (params_.keepClean) {
		out.cleanDepth = depth_;
		out.cleanLabel = label_;
	} else {
		out.gtLabel.clear();
	}
	return out;
}

} // namespace ihf
