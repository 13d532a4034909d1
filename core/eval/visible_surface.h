// SPDX-License-Identifier: MIT
#pragma once

// Visible Surface Discrepancy (Hodan et al., "On Evaluation of 6D Object
// Pose Estimation", ECCV workshops 2016), as the BOP toolkit computes it
// (pose_error.vsd with the "bop19" visibility): the object is rendered alone
// at the estimate and at the truth. A render's visible pixels are those
// where it is not behind the test image's depth by more than delta, or where
// the test image has no depth; the estimate's also take in the truth's
// visible pixels that it covers. Over the union U of the two visible masks a
// pixel costs 1 when it is in one mask only, or when the two renders'
// distances from the camera centre differ by tau or more:
//
//   e_VSD = (pixels of cost 1) / |U|        (1 when U is empty)
//
// Only the surface the sensor sees is compared, so a pose that differs from
// the truth only where the object is hidden (a cup's handle turned behind
// its body) scores as the truth does: the measure for poses that depth alone
// cannot tell apart, where ADD counts a coin flip. BOP 2019 settings:
// delta = 15 mm; tau = 0.05, 0.10, ..., 0.50 of the diameter; an estimate
// is correct at (tau, theta) when e_VSD < theta, theta = 0.05, ..., 0.50;
// AR_VSD is the recall averaged over these 100 pairs (evaluation.h).

#include <span>
#include <vector>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"
#include "core/render/depth_renderer.h"

namespace ihf {

inline constexpr double kVsdDeltaMm = 15.0;

// 0.05, 0.10, ..., 0.50: tau as a share of the diameter, and theta.
std::vector<double> vsdTauShares();
std::vector<double> vsdThetas();

// Scores poses of one object. Offline: each call allocates its renders.
class VisibleSurfaceScorer
{
public:
	// mesh must outlive the scorer.
	explicit VisibleSurfaceScorer(const Mesh &mesh);

	// e_VSD of est against gt for each tau (mm), seen by a camera with
	// intrinsics K whose depth image (mm, 0 = no data) is testDepth; the
	// image's size is the camera's. kInvalidArgument when K has no focal
	// length or the image is empty.
	Expected<std::vector<double>> errors(const Pose &est, const Pose &gt,
					     ImageView<const float> testDepth, const CameraIntrinsics &K,
					     std::span<const double> tausMm);

private:
	const Mesh &mesh_;
	DepthRenderer renderer_;
};

} // namespace ihf
