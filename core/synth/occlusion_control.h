// SPDX-License-Identifier: MIT
#pragma once

// Drives the target's occlusion (1 - visib_fract, BOP's definition: visible
// pixels over the whole silhouette, so the part outside the image counts as
// occluded) to a sampled goal: clutter that hides too much is moved or
// removed; occluders are stood on the table between the camera and the
// target and slid sideways (bisection on the lateral offset) until the
// measured occlusion meets the goal; sometimes the camera is turned so the
// image border cuts the target instead.

#include <vector>

#include "core/common/expected.h"
#include "core/synth/scene_layout.h"
#include "core/synth/scene_render.h"

namespace ihf {

// Which target pixels other objects hide, from one render per object into
// the crop of the target's in-image silhouette.
class OcclusionMeter
{
public:
	OcclusionMeter(SceneRenderer &renderer, const ObjectSilhouette &target,
		       const Pose &worldToCamera);

	// Mask over the crop: 1 where obj lies in front of the target.
	Expected<std::vector<uint8_t>> cover(const SceneObject &obj);
	// 1 - visible / pxCountAll, visible = in-image target pixels no mask covers.
	double occlusion(const std::vector<std::vector<uint8_t>> &covers) const;
	// Occlusion by the image border alone.
	double truncation() const;
	static int count(const std::vector<uint8_t> &mask);

private:
	SceneRenderer &renderer_;
	const ObjectSilhouette &target_;
	Pose worldToCamera_;
	int cx0_ = 0, cy0_ = 0, cw_ = 0, ch_ = 0; // crop, image coordinates
	int inImage_ = 0;
	std::vector<float> scratch_;
};

struct OcclusionGoal {
	double goal = 0;           // sampled occlusion to reach
	double min = 0, max = 0.6; // the range every image must meet
	double tolerance = 0.03;
	double truncationProbability = 0.1; // use the image border for part of it
};

struct OcclusionOutcome {
	double occlusion = 0; // as measured by the meter
	double truncation = 0;
	int occluders = 0;
	int clutterMoved = 0;
	int clutterRemoved = 0;
};

class OcclusionController
{
public:
	OcclusionController(const LayoutSampler &sampler, SceneRenderer &renderer)
		: sampler_(sampler), renderer_(renderer) {}

	// Adjusts layout (camera aim, clutter, occluders); call before addRoom.
	Expected<OcclusionOutcome> apply(SceneLayout &layout, const OcclusionGoal &goal,
					 SynthRandom &rng);

private:
	Status placeTruncation(SceneLayout &layout, const OcclusionGoal &goal, SynthRandom &rng,
			       OcclusionOutcome &out);
	Expected<bool> addOccluder(SceneLayout &layout, OcclusionMeter &meter,
				   std::vector<std::vector<uint8_t>> &covers, double goal,
				   double tolerance, SynthRandom &rng);

	const LayoutSampler &sampler_;
	SceneRenderer &renderer_;
};

} // namespace ihf
