// SPDX-License-Identifier: MIT
#pragma once

// Rotation proposals at a voted translation from the view templates
// (view_templates.h), not in the paper. The forest's rotation votes are
// weak under occlusion (BENCHMARKS.md: ~1 % of the vote weight within 20 deg
// of the truth) while its translation votes are good, so every rotation of
// the template set (viewpoints x in-plane turns) is verified at the voted
// translation with the score's own rule (inliers against the scene seen
// through the model, weighted, and lightly against occlusion; times the
// agreement with the box), evaluated on the templates' points instead of a
// rendering. The translation's depth is first moved to the median depth
// residual of the rotation's points, which absorbs the offset between the
// voted centre and the visible surface. The best distinct rotations are
// returned for the full score and the polish.
// No allocation: fixed-size stack scratch per task (kMaxViewPoints points),
// coarse candidates in the caller's workspace or on the stack.

#include <algorithm>
#include <span>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/geometry/open_sides.h"
#include "core/geometry/pose.h"
#include "core/pose/view_templates.h"
#include "core/runtime/worker_pool.h"

namespace ihf {

inline constexpr int kMaxViewPoints = 256;
inline constexpr int kMaxCoarseKeep = 2048;
inline constexpr int kMaxRefineTop = 64;
inline constexpr int kMaxViewKeep = 16; // proposals per search (keep)
inline constexpr int kMaxInplane = 360; // in-plane turns per viewpoint

struct ViewSearchConfig {
	int inplane = 24;      // in-plane turns per viewpoint (15 deg); 0: search off
	int centres = 1;       // distinct best voted translations searched
	int keep = 6;          // proposals per translation
	float inlierMm = 12.0f;
	float maxShiftMm = 80.0f; // depth alignment range (0: no alignment)
	float outlierWeight = 3.0f;
	float occludedWeight = 0.2f;
	float residualWeight = 0.0f; // the score's inlier weighting by residual
	// The score's agreement with the box (ScoreConfig::boxWeight), on the
	// extent of a rotation's points: (inside * fill')^boxWeight. 0: off.
	float boxWeight = 0.0f;
	float boxMinFill = 0.5f;
	float boxMargin = 0.1f;
	float distinctDeg = 20.0f; // proposals closer than this in rotation are one
	// Each rotation is also tried at the translation that centres its
	// projected points on the optical axis, which passes through the given
	// box's centre in the virtual crop (the box taken as amodal, like the
	// score's box factor); the better of the two is kept.
	bool boxCentre = true;
	// On an axis the frame clipped on one side the rotation's extent goes
	// against the box's other side, and also edgeInsets more times, each
	// edgeInsetShare of the extent further inside: a box drawn round the
	// object with a margin (the LM-O protocol: 10 % larger; a detector's
	// slack) has the object's far edge inside its own, and a rotation
	// placed tens of millimetres off scores below wrong ones before the
	// climb could move it (without the insets synkaz boxes at the border
	// are lost at three times the rate of the others). 0: the edge only.
	int edgeInsets = 2;
	float edgeInsetShare = 0.075f;
	// On an axis the box is trusted on, the box-centred placement is also
	// tried this share of the rotation's extent to either side: a box off
	// centre by a few percent (ihf synth shifts its boxes by up to 10 %, a
	// detector's jitter) puts the true rotation millimetres off, where
	// wrong ones outscore it before the climb (synkaz fixed: 0.917 at 0.06
	// against 0.897 centred only, the view search twice as long). 0:
	// centred only.
	float centreShiftShare = 0.06f;
	// Each rotation placed where the box's size puts it (a box round the
	// whole object, trusted on both axes): box-centred at the depth where
	// its extent fills the box and at 1.1 times that (a box drawn 10 %
	// larger than the object), instead of at the centre's or anchor's
	// depth, which only seeds the extent. The depth alignment then takes
	// only residuals from the inlier band behind: what the sensor sees in
	// front is an occluder. An object mostly hidden by an occluder in
	// front has the box's densest depth and every depth centre on the
	// occluder, and the votes too; a rotation placed there lies on it.
	// Set by the caller for a search of its own (boxSizeSearch).
	bool placeBySize = false;
	// A box trusted on both axes is searched once more so, after the
	// other searches (unbudgeted nearsym mean F1 0.769 against 0.779 with
	// it, lmosym 0.931 against 0.937; BENCHMARKS.md). Never for boxes
	// round the visible part only (firmware_app: BoxKind).
	bool boxSizeSearch = true;
	// Under a frame budget (0: centred only).
	float budgetCentreShiftShare = 0.06f;
	// On a depth centre in a box trusted on both axes the coarse pass
	// scores each rotation at its box-centred translation only; the centre
	// itself (the box's ray: the model's origin on it) joins in the fine
	// pass. The two differ by the offset of the origin from the middle of
	// what the view shows, and the coarse pass only ranks: half its cost
	// (BENCHMARKS.md). true: both in the coarse pass too.
	bool coarseAtCentre = false;
	// Coarse-to-fine: every rotation is first scored on an even subset of
	// coarsePoints of its view's points; only the coarseKeep best are
	// scored on all of them. 0: one pass on all points.
	int coarsePoints = 32;
	int coarseKeep = 1024; // at most kMaxCoarseKeep
	// The shifted placements (centreShiftShare) are four tallies more a
	// rotation: with coarseShifted > 0 the coarse pass tries them only on
	// the coarseShifted x coarseKeep rotations that rank best at their
	// other placements (at most kMaxCoarseKeep). 0: on every rotation.
	int coarseShifted = 0;
	// Centres not from the votes: the densest depth slabs of the box (the
	// initial registration's depth windows), each searched on the box's
	// ray with every rotation's visible points put at the slab's median
	// depth. The forest's translation votes miss some boxes entirely
	// (BENCHMARKS.md); the box and the depth alone still place the object.
	int depthCentres = 3;
	float anchorShare = 0.5f; // of the box's width and height around its centre giving the median
	// Also the medians of as many slabs this thick (in object diameters)
	// that lie in front of all those: a slab a diameter thick holds a
	// large object's surface and the background a few centimetres behind
	// it, and its median then lies between the two. 0: off.
	float depthCentreWidth = 0.5f;
	// The given box is off by some percent, so the box-centred translation
	// is off sideways by millimetres, enough for a wrong rotation to score
	// above the true one. The refineTop best distinct rotations of the last
	// pass therefore climb the sparse score sideways (steps of
	// lateralStepMm, halved twice, depth re-aligned at each) before the
	// `keep` best are chosen. 0: off.
	float lateralStepMm = 4.0f;
	// The same climb also turns about the camera axes by this much (halved
	// twice): the template grid's rotations are up to ~10 deg from any
	// pose. 0: sideways only.
	float rotationStepDeg = 8.0f;
	int refineTop = 64; // at most kMaxRefineTop
	// Under a frame budget (the device) the cheaper climb: fewer climbers,
	// with the turns (they win at 10 to 33 ms on two current x86 cores;
	// on a machine with a search several times slower their time buys more
	// as a further centre; BENCHMARKS.md).
	float budgetRotationStepDeg = 8.0f;
	int budgetRefineTop = 24;
	// and a cheaper coarse pass, so that the search fits a frame at all
	// (the templates' viewpoints are fewer too: ViewTemplateConfig); 32
	// coarse points with the turns score higher than 16 without them.
	int budgetCoarsePoints = 32;
	int budgetCoarseKeep = 256;
	// and the shifted placements on the best few (a quarter less search
	// time: more searches fit a 33 ms frame; BENCHMARKS.md).
	int budgetCoarseShifted = 4;
	// and at most this many depth centres (a third search fits beside the
	// ICP polish because the search is fast; with a search twice as slow it
	// left the polish no time; BENCHMARKS.md).
	int budgetDepthCentres = 3;
	// and the thinner slabs' centres only if this is set (0: none).
	float budgetDepthCentreWidth = 0.0f;
	// Inside a budget every search after the first must leave room for
	// this many ICP polish rounds after it: in a short frame the searches
	// would otherwise take all the time and the polish none (20 ms frames).
	// 0: searches while they fit.
	int budgetPolishRounds = 2;
	// Search the depth centres before the voted ones: where the frame has
	// room for one search or two, the box's depth places the object more
	// often than the votes (at 33 ms the depth centres' proposals came
	// near the truth in 160 ape boxes of 200, the voted centre's in 114,
	// in 8 of them alone; BENCHMARKS.md). Unbudgeted every
	// centre is searched; the order only ranks equal proposals.
	bool depthFirst = false;
	bool budgetDepthFirst = true;
	// A box whose share of its frame is shorter than leanSearchBelow of
	// the budget's searches, as measured so far, searches with the lean
	// settings below (0: never): with a few milliseconds a box (several
	// boxes to a frame) the budget's search leaves no time for the polish,
	// or does not fit at all (BENCHMARKS.md). Counted in
	// searches, not milliseconds, so that a slower machine turns lean
	// at a longer share.
	float leanSearchBelow = 2.5f;
	float leanRotationStepDeg = 0.0f;
	int leanCoarsePoints = 16;
};

// The settings a search inside a frame budget runs with.
inline ViewSearchConfig underBudget(ViewSearchConfig c)
{
	c.rotationStepDeg = c.budgetRotationStepDeg;
	c.refineTop = std::min(c.refineTop, c.budgetRefineTop);
	c.coarsePoints = c.budgetCoarsePoints;
	c.coarseKeep = c.budgetCoarseKeep;
	c.coarseShifted = c.budgetCoarseShifted;
	c.depthCentres = std::min(c.depthCentres, c.budgetDepthCentres);
	c.depthCentreWidth = c.budgetDepthCentreWidth;
	c.depthFirst = c.budgetDepthFirst;
	c.centreShiftShare = c.budgetCentreShiftShare;
	return c;
}

// The settings of a budget's search in a share of few searches
// (leanSearchBelow).
inline ViewSearchConfig underLeanBudget(const ViewSearchConfig &c)
{
	ViewSearchConfig r = underBudget(c);
	r.rotationStepDeg = c.leanRotationStepDeg;
	r.coarsePoints = c.leanCoarsePoints;
	r.centreShiftShare = 0.0f; // a few milliseconds: no shifted placements
	return r;
}

// What the window (the given box) says about the object's place: which
// axes may centre a rotation (not one the frame clipped: the box's centre
// there is not the object's), and which sides the frame clipped (a model
// point past one is unseen, not outside the box, and on an axis clipped on
// one side a rotation is placed against the other).
struct BoxAxes {
	bool x = true;
	bool y = true;
	OpenSides open;
};

struct ViewProposal {
	Pose pose;       // in the camera of `observed`
	float score = 0; // sparse score in [0, 1], on view's points
	int view = -1;   // the template whose points scored it: nearest the pose once the climb turned it
	int turn = -1;   // the in-plane turn it started from
};

// A rotation the coarse pass kept.
struct ViewCoarseCandidate {
	float score;
	int view, turn;
};

// A kept rotation's score on all points and its translation.
struct ViewFineResult {
	float score;
	Eigen::Vector3f t;
};

// Scratch of a search spread over a pool's threads: one coarse heap per
// thread and the fine pass' results.
struct ViewSearchWorkspace {
	std::span<ViewCoarseCandidate> heaps; // viewSearchHeapSize(threads)
	std::span<ViewFineResult> fine;       // kMaxCoarseKeep
};

inline size_t viewSearchHeapSize(int threads)
{
	return static_cast<size_t>(threads) * kMaxCoarseKeep;
}

inline int viewSearchSize(const ViewTemplates &t, const ViewSearchConfig &c)
{
	return t.empty() || c.inplane <= 0 ? 0 : t.viewpoints * c.inplane;
}

// The rotation (model -> camera) of view v turned by `turn` of `inplane`.
Eigen::Matrix3d viewRotation(const ViewTemplates &t, int inplane, int v, int turn);

// Every rotation at `centre` (camera coordinates of the model origin),
// scored against `observed` (depth in mm, 0 = missing) through K; the best
// distinct ones are written to `out` (at most out.size(), best first).
// Returns how many. With anchorDepth > 0 each rotation's depth is instead
// chosen to put the median depth of its points at anchorDepth (mm), centre's
// x and y kept. With a pool and a workspace for its threads the rotations
// are spread over them; the proposals are the same for any number of
// threads (one thread on stack scratch without them).
size_t searchViews(const ViewTemplates &templates, const ViewSearchConfig &config,
		   ImageView<const float> observed, const CameraIntrinsics &K,
		   const Eigen::Vector3d &centre, std::span<ViewProposal> out, BoxAxes box = {},
		   float anchorDepth = 0.0f, WorkerPool *pool = nullptr, ViewSearchWorkspace workspace = {});

// The view whose direction is nearest the one from which `pose` (model ->
// camera) shows the model: from the model's origin along its ray towards
// the camera. -1 when the templates are empty or the origin is not in
// front of the camera.
int nearestView(const ViewTemplates &templates, const Pose &pose);

// The centroid (model frame) of view v's points: the middle of the surface
// a pose near that view shows, without a render.
Eigen::Vector3d viewCentroid(const ViewTemplates &templates, int v);

// searchViews' sparse score of one pose (not only a template's rotation):
// the points of view v (nearestView's) posed by `pose` and tallied against
// `observed`, after the translation has been moved along its ray by their
// median depth residual (config.maxShiftMm > 0), which `aligned` receives.
// A few hundred point projections instead of a render: screens many poses
// for the few worth a full score.
float sparsePoseScore(const ViewTemplates &templates, int v, const ViewSearchConfig &config,
		      ImageView<const float> observed, const CameraIntrinsics &K, const Pose &pose, BoxAxes box,
		      Eigen::Vector3d &aligned);

} // namespace ihf
