// SPDX-License-Identifier: MIT
#pragma once

// IHF inference for one object in one given box (paper Sect. III-C):
//  1. the box becomes a virtual on-axis crop (virtual_crop.h);
//  2. initial registration (Eq. 8): normalise (s_0 = 1), fit the IBS,
//     extract the coarsest parts, pass them down the forest, and take the
//     vote modes; each mode is scored by rendering it (hypothesis_score.h);
//  3. iterative refinement (Eq. 10-13), k times: keep only the crop pixels
//     inside the best hypothesis' depth range [gamma psi1, beta psi2],
//     renormalise (the object grows in the unit cube, so variable-size parts
//     get finer), re-fit, vote again; the best-scoring hypothesis so far is
//     kept;
//  4. optionally a projective ICP polish (icp_refiner.h) of the few best
//     distinct hypotheses of all iterations; the best score wins.
// Hypotheses are scored by depth consistency with the crop and agreement
// with the given box (hypothesis_score.h).
// All frame-path memory is one arena allocated at construction and sized
// from EstimatorLimits (arenaBytes()): persistent buffers at its bottom, the
// per-box scratch (sized to the box's window) above them; estimate() does
// not allocate. Boxes larger than the window limit are processed
// downsampled (virtual_crop.h).
//
// Frame budget: beginFrame()/endFrame() bracket the boxes of one frame,
// which share EstimatorConfig::frameBudgetMs (a lone estimate() call is a
// frame of one box). The crop and the initial registration's first depth
// slab always run; each further slab, each refinement iteration (both with
// room for the polish after them), and the ICP polish, runs only if its cost
// predicted from the measured per-stage running averages fits in the box's
// share, so the estimate is anytime: cut short, it returns the best
// hypothesis so far.
// Per-stage times, budget stops and overruns are counted (stats()).

#include <optional>
#include <span>

#include "core/common/expected.h"
#include "core/common/image.h"
#include "core/estimation/budget_planner.h"
#include "core/estimation/depth_windows.h"
#include "core/estimation/estimator_config.h"
#include "core/estimation/estimator_stats.h"
#include "core/estimation/hypothesis_score.h"
#include "core/estimation/icp_polisher.h"
#include "core/estimation/icp_refiner.h"
#include "core/estimation/pose_scorer.h"
#include "core/estimation/rival_poses.h"
#include "core/features/cloud_point.h"
#include "core/features/part_extractor.h"
#include "core/features/unit_cube_frame.h"
#include "core/ibs/ibs_fitter.h"
#include "core/model/object_model.h"
#include "core/pose/half_turns.h"
#include "core/pose/view_search.h"
#include "core/pose/vote_modes.h"
#include "core/render/depth_renderer.h"
#include "core/runtime/arena.h"

namespace ihf {

struct EstimatorLimits {
	int maxWindowPixels = 200 * 200;
	int maxParts = 3000;
	int maxPartControlPoints = 256;
	int maxVotes = 3000 * 3 * 16;
	int maxActive = 120000;
	int maxIbsPoints = 4000;
	int maxIbsN = 100;
	size_t maxMeshVertices = 50000;
	int maxHistogramDims = 1024; // HoCP length of the forests
	int maxModes = 32;           // vote modes per iteration (translation x rotation)
	int maxModeSeeds = 64;
	int maxCandidates = 16;      // distinct hypotheses kept over the iterations
	int maxRivals = 256;         // scored hypotheses kept for the confidence's margin (the best)
	int threads = 1;             // threads of a box's searches, the caller included (0: one per core)
};

// One scored hypothesis, reported to an EstimateObserver (debugging, the
// `--trace` of ihf estimate, iteration pictures).
struct HypothesisEvent {
	int iteration = 0;   // 0: initial registration, k: refinement k
	const char *stage = ""; // "mode", "icp", "given"
	int rank = 0;        // mode rank within the iteration
	Pose pose;           // model -> real camera
	HypothesisScore score;
	float voteDensity = 0;
};

// The votes of one pass, before mode finding (debugging: does the forest
// vote for the true pose at all, or does mode finding lose it?).
struct VoteEvent {
	int iteration = 0;
	int pass = 0;                       // depth window of the initial registration
	Eigen::Matrix3d cropRotation;       // virtual crop camera -> real camera
	std::span<const CastVote> votes;    // in the virtual crop camera
};

class EstimateObserver
{
public:
	virtual ~EstimateObserver() = default;
	virtual void onHypothesis(const HypothesisEvent &event) = 0;
	virtual void onVotes(const VoteEvent &) {}
};

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

	const EstimatorLimits &limits() const { return limits_; }

	// Arena bytes for the limits: persistent buffers plus the scratch of a
	// box of maxWindowPixels.
	static size_t arenaBytes(const EstimatorLimits &limits);
	// False if the arena could not be allocated or carved; estimate() then
	// returns "no pose" with that reason.
	bool valid() const { return valid_; }
	// High-water mark of the arena: what the largest box so far needed.
	size_t arenaUsed() const { return arena_.highWater(); }
	size_t arenaCapacity() const { return arena_.capacity(); }

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
	void setObserver(EstimateObserver *observer) { observer_ = observer; }

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

	struct Hypothesis {
		Pose pose; // virtual camera frame
		HypothesisScore score;
		int iteration = -1;
		bool valid = false;
	};

	int buildCloud(ImageView<const float> depth, const CameraIntrinsics &K,
		       const ModelParams &params);
	int voteOnce(const CameraIntrinsics &K, const ObjectModel &model,
		     const EstimatorConfig &config, int cloudCount, const UnitCubeFrame *frame,
		     int &parts);
	bool hypothesisFrame(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model,
			     UnitCubeFrame &frame);
	Hypothesis scoreModes(int iteration, size_t modeCount, const CameraIntrinsics &K,
			      const ObjectModel &model, const EstimatorConfig &config);
	// Ranks h among the kept hypotheses (and, unless it is a refinement
	// iteration's, among the registration's).
	void keep(const Hypothesis &h, float sameTranslationMm, bool fromRefinement = false);
	static void keepIn(std::span<Hypothesis> kept, size_t &count, const Hypothesis &h,
			   float sameTranslationMm);
	void searchViewTemplates(const CameraIntrinsics &K, const ObjectModel &model,
				 const EstimatorConfig &config);
	// One view search at `centre` (anchored in depth when anchor > 0), its
	// proposals scored in full and reported under `stage`; returns how many
	// (at most out.size()).
	size_t searchScored(const CameraIntrinsics &K, const ObjectModel &model, const EstimatorConfig &config,
			    const Eigen::Vector3d &centre, float anchor, const char *stage, std::span<Hypothesis> out);
	// Refinement's re-search, at most maxRounds rounds from `best` (`rounds`
	// gets how many ran); returns the best hypothesis found, `best` when none
	// is better. Each round must fit the budget.
	Hypothesis researchAtBest(const CameraIntrinsics &K, const ObjectModel &model, const EstimatorConfig &config,
				  const Hypothesis &best, int maxRounds, int &rounds);
	// Half-turns of the best distinct polished hypotheses (half_turns.h)
	// about the model's box centre; returns the best found, or `best` when
	// none scores higher.
	Hypothesis searchHalfTurns(const CameraIntrinsics &K, const ObjectModel &model,
				   const EstimatorConfig &config, std::span<const Hypothesis> polished,
				   const Hypothesis &best, const Eigen::Vector3d &centre);
	// What the window's box says about the object's place (view_search.h).
	BoxAxes boxAxes() const;
	// One source's turns when HalfTurnConfig::screen is set: placed and
	// screened on the view templates, only the best few rendered.
	void screenHalfTurns(const CameraIntrinsics &K, const ObjectModel &model, const EstimatorConfig &config,
			     const Hypothesis &source, const Eigen::Vector3d &centre, int keepN, int rankBase,
			     Hypothesis &found);
	// The kept turns polished, reported; found takes any better one.
	void polishTurns(std::span<const Hypothesis> top, const CameraIntrinsics &K, const ObjectModel &model,
			 const EstimatorConfig &config, int rankBase, Hypothesis &found);
	// The pose rendered with the model's render mesh into renderView_ (cleared
	// first); false if the render failed.
	// slot: the renderer and render buffer of one pool thread (0: the
	// caller's, renderView_), so that threads can score side by side.
	bool renderPose(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model, int slot = 0);
	// The current box's window as the scorer sees it.
	ScoreWindow scoreWindow(const CameraIntrinsics &K, const EstimatorConfig &config) const;
	template <typename F>
	bool forEachShownPoint(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model, F &&f,
			       int slot = 0);
	std::optional<Eigen::Vector3d> shownCentroid(const Pose &pose, const CameraIntrinsics &K,
						     const ObjectModel &model, int slot = 0);
	// ICP on the crop cut to h's depth range, then the score: the polished
	// hypothesis, or an invalid one when ICP could not run. The time before
	// it is charged to `stage`, the ICP and its score to kIcp.
	// `icp`: config.icpConfig, or the winner's last polish's gates.
	Hypothesis polishIcp(const Hypothesis &h, const CameraIntrinsics &K, const ObjectModel &model,
			     const EstimatorConfig &config, Stage stage, const IcpConfig &icp);
	// The same on a pool thread's slot (its own mask, cloud and render),
	// without the clock: the caller charges the round, and the clock is
	// read by the calling thread alone.
	Hypothesis polishIcpIn(const Hypothesis &h, const CameraIntrinsics &K, const ObjectModel &model,
			       const EstimatorConfig &config, int slot, const IcpConfig &icp);
	// polishIcp() on one thread, polishIcpIn() on several.
	Hypothesis polishOn(const Hypothesis &h, const CameraIntrinsics &K, const ObjectModel &model,
			    const EstimatorConfig &config, Stage stage, int slot, const IcpConfig &icp);
	// A polish as a hypothesis of `iteration` (invalid when ICP could not run).
	static Hypothesis fromPolish(const PolishResult &polished, int iteration);
	// Their shared tail: ICP from the cloud on the slot's renderer, then the score.
	Hypothesis icpAndScore(const Hypothesis &h, std::span<const CloudPoint> cloud, const CameraIntrinsics &K,
			       const ObjectModel &model, const EstimatorConfig &config, int slot,
			       const IcpConfig &icp);
	// The hypotheses the polish runs on, into out; returns their count.
	size_t polishCandidates(const EstimatorConfig &config, double diameter,
				const Hypothesis (&forestBest)[2], std::span<Hypothesis> out) const;
	// The first `max` distinct translations (0.1 diameter apart) of kept_.
	int keptCentres(double diameter, int max, Eigen::Vector3d *centres) const;
	// Every scored hypothesis passes here: a rival for the confidence, and
	// an event for the observer.
	void report(int iteration, const char *stage, int rank, const Pose &virtualPose,
		    const HypothesisScore &s, float density);
	HypothesisScore score(const Pose &pose, const CameraIntrinsics &K, const ObjectModel &model,
			      const EstimatorConfig &config, int slot = 0);
	// Scores poses[i] into scores[i], spread over the pool's threads.
	void scoreAll(std::span<const Pose> poses, std::span<HypothesisScore> scores, const CameraIntrinsics &K,
		      const ObjectModel &model, const EstimatorConfig &config);
	DepthRenderer &rendererOf(int slot) { return slot == 0 ? renderer_ : moreRenderers_[slot - 1]; }
	ImageView<float> &renderViewOf(int slot) { return slot == 0 ? renderView_ : moreRenderViews_[slot - 1]; }
	// The render views of every slot over render_ (one window each).
	void setRenderViews(int w, int h);
	// Every renderer skips back faces when the config asks and the model's
	// render mesh allows it.
	void setCulling(const ObjectModel &model, const EstimatorConfig &config);
	void maskToHypothesis(const HypothesisScore &s, const EstimatorConfig &config);
	void maskToRange(float lo, float hi);
	void maskToRange(float lo, float hi, std::span<float> out) const;

	// Members only, no arena: for arenaBytes().
	PoseEstimator(const EstimatorLimits &limits, const Clock *clock, int);

	template<typename A>
	bool carvePersistent(A &arena);
	template<typename A>
	bool carveBox(A &arena, size_t pixels);
	void releaseBox();
	// Tells the planner what the box runs after its vote passes.
	void planAfterPasses(const EstimatorConfig &config, int requestedIterations, const ObjectModel &model);
	// Rounds of the pool's threads that polish this many hypotheses.
	int polishRounds(size_t polishes) const;

	EstimatorLimits limits_;
	Arena arena_;
	bool valid_ = false;
	size_t persistentBytes_ = 0;
	IbsFitter fitter_;
	PartExtractor extractor_;
	DepthRenderer renderer_;
	WorkerPool workers_; // started with the arena, idle between searches
	// The other pool threads' renderers and render views (slots 1...).
	std::array<DepthRenderer, WorkerPool::kMaxThreads - 1> moreRenderers_;
	std::array<ImageView<float>, WorkerPool::kMaxThreads - 1> moreRenderViews_;

	// Clock, stage timer, frame budget, cost models and the box's plan:
	// asked before every stage that can be cut.
	BudgetPlanner planner_;
	StageTimer &timer_ = planner_.timer(); // each stage laps it
	uint64_t researches_ = 0, researchWins_ = 0;
	EstimatorPeaks peaks_;

	// Persistent (sized from the limits).
	std::span<float> observed_; // virtual crop
	std::span<ControlPoint> active_;
	std::span<Part> parts_;
	std::span<PartCp> pool_;
	std::span<float> hist_;
	std::span<CastVote> votes_;
	std::span<float> modeScratch_;
	std::span<uint32_t> modeSupport_;
	std::span<Eigen::Vector4f> modePacked_;
	std::span<float> modeThreadScratch_; // the other threads' (threads - 1 x maxVotes)
	std::span<uint32_t> modeThreadSupport_;
	std::span<Eigen::Vector3f> seeds_;
	std::span<PoseMode> modes_;
	std::span<int> windowHist_;
	std::span<DepthWindow> windows_;
	size_t windowCount_ = 0; // of the current box
	std::span<DepthWindow> anchorWindows_; // the view search's own, when thinner
	std::span<ViewCoarseCandidate> viewHeaps_; // the view search's, per thread
	std::span<ViewFineResult> viewFine_;
	std::span<Hypothesis> kept_; // best distinct hypotheses, by score
	size_t keptCount_ = 0;
	// The same without the refinement iterations' modes.
	std::span<Hypothesis> registrationKept_;
	size_t registrationKeptCount_ = 0;
	std::span<RivalPose> rivalStore_;
	RivalPoses rivals_; // every scored hypothesis of the box (the best maxRivals)
	Eigen::Matrix3d cropRotation_ = Eigen::Matrix3d::Identity();
	OpenSides openSides_; // of the current box: sides on the frame border
	EstimateObserver *observer_ = nullptr;

	// Per box (sized to its window, released after it).
	std::span<float> working_;  // masked crop (Eq. 10)
	std::span<float> render_;
	std::span<CloudPoint> cloud_;
	std::span<float> moreWorking_;       // the other slots' masks (threads - 1 windows)
	std::span<CloudPoint> moreClouds_;   // and clouds
	std::span<Eigen::Vector3f> unit_, normals_;
	ImageView<float> observedView_, workingView_, renderView_;
};

} // namespace ihf
