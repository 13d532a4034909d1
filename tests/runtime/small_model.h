// SPDX-License-Identifier: MIT
#pragma once

// Test helpers of the runtime tests: a small forest trained from an LM-O
// mesh (a few seconds), a clean render of it at a training view placed off
// the optical axis, and a clock that tests drive themselves.

#include <algorithm>
#include <memory>

#include <gtest/gtest.h>

#include "core/forest/forest_trainer.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/rotation.h"
#include "core/model/object_model.h"
#include "core/render/depth_renderer.h"
#include "core/runtime/clock.h"
#include "core/training/hocp_split_metric.h"
#include "core/training/training_set.h"
#include "core/training/view_sampler.h"
#include "tests/common/test_paths.h"

namespace ihf::test {

inline const CameraIntrinsics kKinect{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};

// Every read advances time by a fixed step, so a run's timing is a
// deterministic function of how often the code reads the clock.
class StepClock final : public Clock
{
public:
	explicit StepClock(int64_t stepNs) : step_(stepNs) {}
	int64_t nowNs() const override { return t_ += step_; }
	int64_t peek() const { return t_; }

private:
	int64_t step_;
	mutable int64_t t_ = 0;
};

struct SmallModel {
	std::unique_ptr<OwnedObjectModel> model;
	TrainingSetConfig set;
	std::unique_ptr<TrainingSet> training; // the parts the forest grew from
};

inline SmallModel trainSmallModel(int objId, uint64_t seed, int viewpoints = 30, int inplane = 3)
{
	SmallModel out;
	char name[32];
	std::snprintf(name, sizeof(name), "obj_%06d.ply", objId);
	auto mesh = loadPly(lmoDir() / "models" / name);
	EXPECT_TRUE(mesh.ok());
	if (!mesh)
		return out;
	ModelParams params;
	params.objId = objId;
	params.diameter = meshDiameter(*mesh);
	out.set.views.viewpoints = viewpoints;
	out.set.views.inplaneSteps = inplane;
	out.set.views.minDistance = 750;
	out.set.views.maxDistance = 850;
	out.set.views.seed = seed;
	out.set.scales = {1.0f};
	out.set.partsPerImage = 20;
	out.set.seed = seed;
	auto set = buildTrainingSet(*mesh, kKinect, params, out.set);
	EXPECT_TRUE(set.ok());
	if (!set)
		return out;
	HocpSplitMetric metric(*set, params.hocp, params.depthCheckMarginMm);
	ForestTrainerConfig fc;
	fc.seed = seed;
	HoughForest forest = trainForest(fc, metric, set->labels);
	out.model = std::make_unique<OwnedObjectModel>(params, std::move(*mesh),
						       ForestStorage(forest, TemplateEncoding::kUint8));
	out.training = std::make_unique<TrainingSet>(std::move(*set));
	return out;
}

// The model rendered into depth at gt (added to what depth holds: the
// renderer depth-tests); returns the box around it enlarged by 10%.
inline PixelBox renderInto(const ObjectModel &model, const Pose &gt, DepthImageMm &depth)
{
	DepthRenderer renderer(model.mesh().vertices.size());
	DepthImageMm alone(depth.width(), depth.height(), 0.0f);
	EXPECT_TRUE(renderer.render(model.mesh(), gt, kKinect, alone.view()).ok());
	EXPECT_TRUE(renderer.render(model.mesh(), gt, kKinect, depth.view()).ok());
	int x0 = depth.width(), y0 = depth.height(), x1 = -1, y1 = -1;
	for (int y = 0; y < depth.height(); ++y)
		for (int x = 0; x < depth.width(); ++x)
			if (alone.at(x, y) > 0) {
				x0 = std::min(x0, x);
				y0 = std::min(y0, y);
				x1 = std::max(x1, x);
				y1 = std::max(y1, y);
			}
	const int mx = (x1 - x0) / 20 + 2, my = (y1 - y0) / 20 + 2;
	return {x0 - mx, y0 - my, x1 - x0 + 1 + 2 * mx, y1 - y0 + 1 + 2 * my};
}

// A training view's appearance moved to `t` (the virtual crop undoes the
// off-axis rotation).
inline Pose viewAt(const SmallModel &m, int view, const Eigen::Vector3d &t)
{
	auto views = sampleTrainingViews(m.set.views);
	Pose gt;
	gt.t = t;
	gt.R = rayAlignment(t) * views[static_cast<size_t>(view) % views.size()].pose.R;
	return gt;
}

} // namespace ihf::test
