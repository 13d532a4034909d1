// SPDX-License-Identifier: MIT
#pragma once

// Depth consistency of a pose hypothesis: its rendering compared with the
// observed depth pixel by pixel. Where the model is drawn and depth was
// observed, the pixel is an inlier (within inlierMm), occluded (observed in
// front: something covers the object, which is allowed) or an outlier
// (observed behind: the object would hide what the sensor saw, so the pose
// is wrong there). The score in [0, 1] rewards inliers, punishes outliers
// hard and occlusion lightly, so a correct pose of a 60% occluded object
// still scores above a pose laid on the occluder in front of it.

#include <optional>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/mesh.h"
#include "core/geometry/open_sides.h"
#include "core/geometry/pose.h"

namespace ihf {

struct ScoreConfig {
	float inlierMm = 10.0f;
	// Depth score = inliers / (inliers + wOut outliers + wOcc occluded).
	// An outlier (the scene seen through the model) cannot happen at the
	// true pose, only at edges and in sensor noise; an occluded pixel
	// (something in front) often does, up to most of the object. Weighted
	// 1 / 0.5, a model laid on the occluder in front outscored the truth in
	// a sixth of the synthetic ape boxes. At 3 / 0.2 it still won 25 of
	// the 66 boxes lost on a Kinect-noise benchmark; 0.1 with a box weight
	// of 1.5 gained 0.012 mean F1 over 41 object/forest pairs with amodal
	// boxes, but lost 0.065 with boxes round the visible part. These defaults are for
	// amodal boxes; the tool keeps both sets (firmware_app: BoxKind).
	float outlierWeight = 3.0f;
	float occludedWeight = 0.1f;
	// Agreement with the given box, which is taken to enclose the whole
	// object (an amodal detection, as LM-O's bbox_obj): the score is
	// multiplied by (inside * fill')^boxWeight, where inside is the share of
	// the hypothesis' projected extent inside the box and fill' =
	// min(1, covered box share / boxMinFill). A hypothesis too near (too big
	// for the box) or too far (too small) loses; boxWeight 0 turns it off.
	float boxWeight = 1.5f;
	float boxMinFill = 0.5f;
	float boxMargin = 0.1f; // overhang tolerated, share of the box size
	// A side of the box where at least this share of the rendering's
	// outermost boxOccludedBandPx columns or rows lies behind the scene
	// (occluded) is open to overhang: a box drawn round the visible part
	// of an object (a modal detection) cuts the truth where something
	// hides it. 0: off, for amodal boxes, where it costs (synkaz mean F1,
	// off against 0.5: 0.873 against 0.856 amodal, 0.797 against 0.812
	// modal).
	float boxOccludedSide = 0.0f;
	int boxOccludedBandPx = 2;
	// An inlier counts 1 - residualWeight (e / inlierMm)^2 instead of 1, so
	// a pose whose surface fits to the sensor's noise beats one whose
	// inliers merely fall inside the band (a wrong rotation of a rounded
	// object). 0: every inlier counts 1. Syn200 mean F1 +0.01 to +0.07 per
	// object with 1 against 0.
	float residualWeight = 1.0f;
	// An outlier on the rendering's outline (a 4-neighbour not drawn) is
	// not counted: a structured-light sensor's edges wander by a pixel or
	// so and a time-of-flight camera's edge pixels float between the two
	// surfaces, so the background shows inside the true pose's outline,
	// most of all around a small visible part. Mean F1 +0.012 on the
	// Kinect- and time-of-flight-noise benchmarks, within +-0.002 on the
	// others. false: every outlier counts.
	bool skipEdgeOutliers = true;
	// Where a true pose's model ends, the object ends: just outside its
	// visible outline the sensor sees past it, to something farther (or to
	// an occluder in front). A pose laid on a surface that goes on past its
	// outline (the face of an occluder in front of the object, a wall) has
	// the scene carry on at its own depth there. Each inlier on the outline
	// looks edgeOffsetPx sensor pixels outward (a structured-light edge
	// wanders by one to three): a drop of more than edgeJumpMm behind is an
	// edge, within edgeJumpMm the surface continues (nearer: an occluder,
	// not counted). The score is multiplied by min(1, b / edgeShare), where
	// b is the share of edges, counted with edgePrior pseudo-pixels at
	// edgeShare (a pose with a short outline is left almost alone). True
	// poses mostly show edges at a third or more of their outline, less
	// where they stand on a table; poses laid on an occluder at almost
	// none. Unbudgeted mean F1 with 0.1 against 0: syn200 0.950 / 0.935,
	// lmosym 0.961 / 0.937, nearsym 0.784 / 0.779 (BENCHMARKS.md). 0: off.
	float edgeShare = 0.1f;
	int edgeOffsetPx = 4;
	float edgeJumpMm = 20.0f;
	float edgePrior = 5.0f;
};

struct HypothesisScore {
	int rendered = 0;  // model pixels
	int compared = 0;  // model pixels with observed depth
	int inliers = 0;
	int outliers = 0;
	int occluded = 0;
	float depthScore = 0; // in / (in + out + w occ)
	int edgeDrops = 0;     // outline inliers with the scene dropping away outside
	int edgeContinues = 0; // outline inliers with the scene going on at their depth
	float boxFactor = 1;  // agreement with the given box
	float edgeFactor = 1; // the outline's edges (ScoreConfig::edgeShare)
	float score = 0;      // depthScore * boxFactor * edgeFactor
	float depthMin = 0; // rendered depth range (Eq. 10's gamma, beta)
	float depthMax = 0;
};

// The depth score and the outline's edge counts (and factor), the window
// being `downsample` sensor pixels to its own.
HypothesisScore scoreHypothesis(ImageView<const float> observed, ImageView<const float> rendered,
				const ScoreConfig &config, int downsample = 1);

// The box factor above for a pose in the camera `window` whose image is the
// given box (pixels [0, width) x [0, height)). The projected extent is the
// bounding box of at most ~512 evenly strided mesh vertices. Overhang past
// an open side costs nothing.
float boxAgreement(const Mesh &mesh, const Pose &pose, const CameraIntrinsics &window,
		   const ScoreConfig &config, OpenSides open = {});

// open with the sides added where the rendering is occluded at the box's
// edge (ScoreConfig::boxOccludedSide); open as it is when that is off.
OpenSides occludedSides(ImageView<const float> observed, ImageView<const float> rendered,
			const ScoreConfig &config, OpenSides open);

} // namespace ihf
