// SPDX-License-Identifier: MIT
#pragma once

// How alike an object looks to itself turned about an axis, seen as the
// estimator sees it: depth views from viewpoints all round the object, each
// rendered plain and turned, compared pixel by pixel. A pixel differs where
// one render draws and the other does not, or where their depths lie more
// than a share of the object's diameter apart (so that a small turn of a
// compact object is not taken for a near-symmetry). A view's share is its
// differing pixels over the pixels either render draws. Training time: the
// plain views are rendered once, at construction (allocates).

#include <vector>

#include <Eigen/Core>

#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/pose.h"
#include "core/render/depth_renderer.h"

namespace ihf {

struct TurnViewsConfig {
	int viewpoints = 32;        // directions on the sphere, quasi-uniform
	int imageSize = 96;         // square views, pixels
	double pixelsAcross = 64;   // the object's diameter in a view, pixels
	double toleranceShare = 0.05; // depths closer than this share of the diameter agree
	double alikeShare = 0.3;    // a view whose share is at most this looks alike
};

// What a turn does to the views.
struct TurnLook {
	double meanShare = 1;  // differing share, mean over the views
	double alikeViews = 0; // share of the views that look alike (at most alikeShare differs)
};

class TurnViews
{
public:
	TurnViews(const Mesh &mesh, const TurnViewsConfig &config = {});
	// The turn by deg degrees about the axis through point (model frame).
	// Gives up once the mean share is sure to exceed giveUpAbove: then
	// meanShare is above it (what the views so far add up to) and
	// alikeViews is not counted.
	TurnLook compare(const Eigen::Vector3d &axis, const Eigen::Vector3d &point, double deg,
			 double giveUpAbove = 1.0);

private:
	const Mesh &mesh_;
	TurnViewsConfig config_;
	CameraIntrinsics K_;
	float tolerance_ = 0; // mm
	DepthRenderer renderer_;
	std::vector<Pose> poses_;
	std::vector<float> plain_;  // the plain views, one after another
	std::vector<float> turned_; // one view's scratch
};

} // namespace ihf
