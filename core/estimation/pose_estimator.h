// SPDX-License-Identifier: MIT
#pragma once

// IHF inference for one object in one given box (paper Sect. III-C):
//  1. the box becomes a virtual on-axis crop (virtual_crop.h);
//  2. initial registration (Eq. 8): normalise (s_0 = 1), fit the IBS,
//     extract the coarsest parts, pass them down the forest, and take the
//     vote modes (hough_voter.h); each mode is scored by rendering it
//     (box_scorer.h, hypothesis_score.h) and the best distinct ones are
//     kept (candidate_pool.h);
//  3. iterative refinement (Eq. 10-13), k times: keep only the crop pixels
//     inside the best hypothesis' depth range [gamma psi1, beta psi2],
//     renormalise (the object grows in the unit cube, so variable-size parts
//     get finer), re-fit, vote again;
//  4. proposals the votes did not give (proposal_source.h): the view
//     templates searched at the voted and the depth centres;
//  5. a projective ICP polish (hypothesis_polisher.h) of the best distinct
//     hypotheses, the best polished one winning over every proposal as
//     scored; then proposals at the polished best (a re-search, the
//     half-turns), each taken if it scores higher;
//  6. a nearly symmetric object's best compared with its turns on the pixels
//     where they differ (symmetry_rivals.h);
//  7. the confidence: the score less a close distinct rival's (rival_poses.h),
//     or as the turns' comparison found.
// All frame-path memory is one arena allocated at construction and sized
// from EstimatorLimits (estimator_workspace.h); estimate() does not
// allocate. Boxes larger than the window limit are processed downsampled
// (virtual_crop.h).
//
// Frame budget: beginFrame()/endFrame() bracket the boxes of one frame,
// which share EstimatorConfig::frameBudgetMs (a lone estimate() call is a
// frame of one box). The crop and the initial registration's first depth
// slab always run; each further slab, each refinement iteration, each
// search and each polish round runs only if its cost predicted from the
// measured per-stage running averages fits in the box's share
// (budget_planner.h), so the estimate is anytime: cut short, it returns the
// best hypothesis so far.
// Per-stage times, budget stops and overruns are counted (stats()).

#include <span>

#include "core/common/expected.h"
#include "core/common/fixed_list.h"
#include "core/common/image.h"
#include "core/estimation/budget_planner.h"
#include "core/estimation/candidate_pool.h"
#include "core/estimation/estimate_observer.h"
#include "core/estimation/estimator_config.h"
#include "core/estimation/estimator_stats.h"
#include "core/estimation/estimator_workspace.h"
#include "core/estimation/half_turn_proposals.h"
#include "core/estimation/hough_voter.h"
#include "core/estimation/hypothesis_score.h"
#include "core/estimation/icp_polisher.h"
#include "core/estimation/proposal_source.h"
#include "core/estimation/research_proposals.h"
#include "core/estimation/symmetry_rivals.h"
#include "core/estimation/view_proposals.h"
#include "core/estimation/virtual_crop.h"
#include "core/features/unit_cube_frame.h"
#include "core/model/object_model.h"
#include "core/runtime/clock.h"

namespace ihf {

struct PoseEstimate {
	bool found = false;
	const char *reason = ""; // why no pose, when !found
	Pose pose;               // model -> real camera
	float confidence = 0;    // score.score scaled by the margin (rival_poses.h)
	float margin = 0;        // score.score less the best distinct rival's
	int iterationsDone = 0;
	int researches = 0; // refinement's re-search rounds run (researchRounds)
	int bestIteration = -1;
	int parts = 0;  // of the last iteration
	int votes = 0;
	bool icpApplied = false;
	HypothesisScore score;
	bool budgetStopped = false; // refinement or a candidate search cut short by the frame budget
	bool icpSkipped = false;    // ICP left out by the frame budget
	// A nearly symmetric object whose pose the depth cannot tell from a
	// turn of it about `ambiguityAxis` (camera frame, unit): the part that
	// tells them apart is hidden (symmetry_rivals.h). Its confidence is
	// scaled by EstimatorConfig::symmetryTurns.ambiguousConfidence.
	bool ambiguous = false;
	Eigen::Vector3d ambiguityAxis = Eigen::Vector3d::Zero();
};

// What the warm-up box cost on the estimator's clock. The initial
// registration (from the box's start to its scored vote modes, the span
// `registrationOverruns` checks) runs in every box whatever the budget: a
// frame shorter than it overruns.
struct WarmUpCost {
	double registrationMs = 0;
	double boxMs = 0; // the whole box, view search and polish included
	// A frame shorter than budgetTightMs gives each of its boxes the tight
	// profile; the warm-up box then runs that one too.
	bool tight = false;
	int parts = 0; // the warm-up box's parts
};

class PoseEstimator
{
public:
	// clock: the time source of budget and stage counters (a steady clock
	// if null); it must outlive the estimator.
	explicit PoseEstimator(const EstimatorLimits &limits = {}, const Clock *clock = nullptr);
	PoseEstimator(const PoseEstimator &) = delete;
	PoseEstimator &operator=(const PoseEstimator &) = delete;

	const EstimatorLimits &limits() const { return workspace_.limits(); }

	// Arena bytes for the limits: persistent buffers plus the scratch of a
	// box of maxWindowPixels.
	static size_t arenaBytes(const EstimatorLimits &limits);
	// False if the arena could not be allocated or carved; estimate() then
	// returns "no pose" with that reason.
	bool valid() const { return workspace_.valid(); }
	// High-water mark of the arena: what the largest box so far needed.
	size_t arenaUsed() const { return workspace_.arena().highWater(); }
	size_t arenaCapacity() const { return workspace_.arena().capacity(); }

	// The boxes estimated until endFrame() share budgetMs (<= 0: unlimited).
	void beginFrame(int boxes, float budgetMs);
	void endFrame();

	EstimatorStats stats() const;

	// Start-up, before the first budgeted frame: one box of `model`, rendered
	// in front of a wall, estimated with the budget profile of `config` but
	// no budget, so that every stage a budgeted box may run has a measured
	// cost (a stage never measured is predicted free: the first frame would
	// run it whatever the time left, and overrun). Then forgets the box: the
	// stage, frame and budget counters and the peaks start again from zero;
	// the cost averages and the arena's high-water mark keep it. The object
	// spans most of the largest window (EstimatorLimits::maxWindowPixels),
	// so the first predictions err on the safe, high side. Allocates a
	// K-sized image: not for the frame path. Returns what the box cost.
	Expected<WarmUpCost> warmUp(const ObjectModel &model, const CameraIntrinsics &K,
				    const EstimatorConfig &config);

	// Hypotheses are reported to the observer (nullptr: none). Not owned.
	void setObserver(EstimateObserver *observer) { pool_.setObserver(observer); }

	// Scores a given pose (model -> real camera) in the box as estimate()
	// scores its hypotheses. For diagnostics and tests.
	Expected<HypothesisScore> scorePose(ImageView<const float> depth, const CameraIntrinsics &K,
					    const PixelBox &box, const ObjectModel &model,
					    const EstimatorConfig &config, const Pose &pose);

	// depth: the whole frame in mm (0 = missing). box: x, y, w, h pixels.
	PoseEstimate estimate(ImageView<const float> depth, const CameraIntrinsics &K,
			      const PixelBox &box, const ObjectModel &model,
			      const EstimatorConfig &config);

private:
	// Per estimate() call: starts the box (and a frame of its own when none
	// was begun), releases the box's scratch and closes the box at exit.
	class BoxScope
	{
	public:
		BoxScope(PoseEstimator &e, const EstimatorConfig &config);
		~BoxScope();

	private:
		PoseEstimator &e_;
		ArenaScope scratch_;
		bool ownFrame_;
	};

	// Hypotheses polished per box at most.
	static constexpr size_t kMaxPolished = 64;
	// What the polish produced: the candidates' results, in candidate order.
	struct Polished {
		Hypothesis results[kMaxPolished];
		size_t count = 0;      // polished (the budget may stop before all)
		size_t candidates = 0; // chosen for the polish
		std::span<const Hypothesis> items() const { return {results, count}; }
	};

	// The box's settings: the requested ones, or under a frame budget its
	// share's profile (`budgeted` holds them).
	const EstimatorConfig &boxSettings(const EstimatorConfig &requested, EstimatorConfig &budgeted);
	// The box cropped into the workspace and its scratch carved; null, or
	// why the box cannot be estimated.
	const char *startBox(ImageView<const float> depth, const CameraIntrinsics &K, const PixelBox &box,
			     const ObjectModel &model, const EstimatorConfig &config, VirtualCrop &crop);
	// The crop buffer a box's window is cropped into: the limits' window,
	// or the config's when smaller.
	std::span<float> boxWindowBuffer(const EstimatorConfig &config);
	// A nearly symmetric object's turns compared on the box cropped again
	// at the limits' window (part_window.h), when its own window was cropped
	// coarser; the budget then predicts the comparison by that window's
	// pixels.
	void comparePartsAtFullWindow(ProposalBox &box, ImageView<const float> depth, const CameraIntrinsics &K,
				      const PixelBox &pixelBox, int downsample);
	// The dense depth slabs of the box (depth_windows.h); returns how many.
	size_t findSlabs(const EstimatorConfig &config, double diameter);
	// Tells the planner what the box runs after its vote passes.
	void planAfterPasses(const ProposalBox &box);
	// Iteration k's votes cast with voteCfg (k = 0: the initial
	// registration, one pass per slab; k > 0: a refinement on the masked
	// crop, normalised with `cube` when given), their modes scored and
	// kept; returns the iteration's best.
	Hypothesis voteIteration(ProposalBox &box, int k, const EstimatorConfig &voteCfg, const UnitCubeFrame *cube,
				 PoseEstimate &out);
	// The registration, then k refinement iterations, each under the
	// budget; bests[0] gets the registration's best, bests[1] the last
	// refinement's.
	void voteAndRefine(ProposalBox &box, HypothesisPolisher &polisher, Hypothesis (&bests)[2], PoseEstimate &out);
	// The chosen candidates polished in rounds of the pool's threads, each
	// round under the budget; best takes any better polish.
	void polishCandidates(ProposalBox &box, const Hypothesis (&forestBests)[2], Polished &polished,
			      Hypothesis &best, PoseEstimate &out);
	// The pose in the real camera, its score and confidence.
	void finish(const ProposalBox &box, const Eigen::Matrix3d &cropRotation, const Hypothesis &best,
		    PoseEstimate &out) const;

	EstimatorWorkspace workspace_;
	// Clock, stage timer, frame budget, cost models and the box's plan:
	// asked before every stage that can be cut.
	BudgetPlanner planner_;
	StageTimer &timer_ = planner_.timer(); // each stage laps it
	EstimatorPeaks peaks_;
	HoughVoter voter_{workspace_, timer_, peaks_};
	CandidatePool pool_;
	ViewTemplateSource views_;
	ResearchSource research_;
	HalfTurnSource halfTurns_;
	SymmetryRivalSource symmetryTurns_;
	OpenSides openSides_; // of the current box: sides on the frame border
};

} // namespace ihf
