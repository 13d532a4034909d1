// SPDX-License-Identifier: MIT
#pragma once

// The settings of the pose estimator (pose_estimator.h), and its profiles:
// the settings a box runs with inside a frame budget, inside a tight or a
// short share of its frame, and in a refinement iteration, each derived
// from the base settings by the bounds the budget*, tight*, short* and
// iteration* fields give.

#include "core/estimation/hypothesis_score.h"
#include "core/estimation/icp_refiner.h"
#include "core/estimation/rival_poses.h"
#include "core/estimation/symmetry_turn_config.h"
#include "core/pose/half_turns.h"
#include "core/pose/view_search.h"

namespace ihf {

struct EstimatorConfig {
	int iterations = 5; // k: refinement iterations after the initial registration
	// Refinement also searches the view templates again at the polished
	// best hypothesis' own translation (view_search.h): the registration's
	// searches place each rotation by the box and by depth slabs, which
	// puts the true rotation millimetres to tens of millimetres off where
	// the box is off or clipped, while the polish has moved the best,
	// right or wrong in rotation, onto the object. The new proposals'
	// researchPolish best are polished; another round follows while one
	// improves the best, at most researchRounds and at most `iterations`
	// (k = 0, the initial registration alone: none). Not in the paper.
	int researchRounds = 1;
	int researchPolish = 6;
	float psi1 = 0.97f; // Eq. 10 scaling of the hypothesis' nearest depth
	float psi2 = 1.03f; // and of its farthest
	// Initial registration on the densest depth slabs of the box
	// (depth_windows.h), each depthWindowWidth diameters thick; 0 votes on
	// the whole box as the paper does.
	int depthWindows = 2;
	float depthWindowWidth = 1.0f;
	int maxHypotheses = 6; // translation modes scored per iteration
	int rotationModes = 3; // rotation modes per translation mode
	float translationBandwidth = 0.06f; // of the object diameter
	float rotationBandwidthDeg = 15.0f;
	int maxShiftVotes = 16384; // translation mean shift on at most this many votes (0: all)
	int partStride = 0; // 0: the model's training stride
	int targetParts = 600; // wider stride when a box would give more parts; 0: off
	bool icp = true;
	// Hypotheses are rendered without their back faces when the model's
	// render mesh is closed and wound outwards (ObjectModel::
	// renderMeshClosed()): the same depth at about half the cost.
	bool cullBackFaces = true;
	int icpCandidates = 16; // distinct best hypotheses polished (search, ICP)
	// After a refinement, also the forest's best of the registration and of
	// the last iteration when the ranking leaves them out (up to 2 more).
	bool polishForestBests = true;
	// After a refinement, also the icpCandidates best distinct hypotheses
	// of the registration and the view search alone (what k = 0 would
	// polish, but for the search's centre) when the ranking leaves them
	// out: refinement's modes must not crowd out a candidate the
	// registration alone would have polished to the truth.
	bool polishRegistration = true;
	IcpConfig icpConfig;
	// Every rotation of the model's view templates verified at the best
	// distinct translations (view_search.h); the best join the hypotheses
	// to polish. Not in the paper. Its weights follow `score`.
	ViewSearchConfig views;
	// The best polished hypotheses turned by 180 deg about axes through
	// the model's centre, scored, and the best turns polished too. Not in
	// the paper.
	HalfTurnConfig halfTurns;
	// A nearly symmetric object's best pose compared with its turns about
	// the model's near-symmetries on the pixels where they differ
	// (symmetry_rivals.h); the pose says when the depth cannot tell them
	// apart. Not in the paper.
	SymmetryTurnConfig symmetryTurns;
	// The pose's confidence: its score, less when a distinct rival scored
	// nearly as well (rival_poses.h).
	ConfidenceConfig confidence;
	ScoreConfig score;
	int minValidPixels = 60;
	// Refinement normalises with the unit cube of the whole rendered
	// hypothesis rather than of the (occluded) masked cloud, as training
	// normalises with the whole silhouette; false: the paper's Eq. 1 on
	// the masked cloud.
	bool hypothesisCube = true;
	// Refinement iterations (k > 0) vote leaner than the registration:
	// each bounds its setting as the tight profile's do (0: as the
	// registration). The registration has to find the object; an
	// iteration re-votes on a crop already cut to its hypothesis' depth
	// range, and its modes only add candidates to the polish. At k = 5:
	// the same mean F1 over 16 object-forest-benchmark pairs at 30-37 %
	// less time a box.
	int iterationIbsMaxPoints = 300;
	int iterationIbsCgIterations = 6;
	int iterationMaxShiftVotes = 1024;
	int iterationTargetParts = 100;
	float frameBudgetMs = 0; // per frame, shared by its boxes; 0: unlimited
	// Inside a frame budget, at most this many refinement iterations and
	// depth slabs (-1: as without a budget; the view search has its own,
	// ViewSearchConfig::budget*). On a 33 ms frame their time buys more in
	// the view search and ICP; the iterations stay anytime whatever the
	// bound, each only if the view searches, the polish and the re-search
	// still fit after it (budget_planner.h; -1 at 10 ms, syn200 ape: 0.370
	// with room kept for one polish round alone, 0.895 with the searches').
	int budgetIterations = 0;
	// and at most this many re-search rounds (researchRounds; -1: as
	// without a budget). Not capped by the iterations' bound above: only
	// by the requested k.
	int budgetResearchRounds = 1;
	int budgetDepthWindows = 1;
	// and parts kept near at most this many (targetParts; 0: as without a
	// budget): a large object's registration alone overruns 33 ms at 600,
	// and the time buys more in the view search.
	int budgetTargetParts = 30;
	// The IBS fit of a box, from at most this many depth points and with
	// at most this many CG iterations (0: the forest's own [ibs] values);
	// inside a budget the budget* ones (0: as without a budget). The fit
	// was a third of a 33 ms box; there the votes only place the view
	// search.
	int ibsMaxPoints = 0;
	int ibsCgIterations = 0;
	int budgetIbsMaxPoints = 500;
	int budgetIbsCgIterations = 10;
	// A box whose share of its frame is shorter than budgetTightMs runs a
	// leaner registration still (0: never): at 10 ms the registration took
	// 6-8 of them and left the view search and the polish no room; with
	// these values it takes ~3. With room to
	// spare the fuller vote is worth its time. Each bounds its setting as
	// the budget* ones do (0: as under the budget).
	float budgetTightMs = 24.0f;
	int tightTargetParts = 10;
	int tightMaxShiftVotes = 1024;
	int tightIbsMaxPoints = 300;
	int tightIbsCgIterations = 6;
	int tightMaxHypotheses = 2;
	int tightRotationModes = 2;
	// and searches with at most this share for the view search's shifted
	// placements (ViewSearchConfig::centreShiftShare): they double the
	// search, which a 10 ms box cannot afford (syn200, mean F1 without
	// them against with them: 0.848 against 0.780 at 10 ms; at 33 ms they
	// gain, 0.909 against 0.890).
	float tightCentreShiftShare = 0.0f;
	// And a box whose share is shorter than budgetShortMs polishes with at
	// most shortIcpIterations ICP iterations a round (0: as configured):
	// at 10 ms a round of 10 took ~1 ms, and half of them buy more rounds
	// and searches; at 20 ms the full rounds are worth their time.
	float budgetShortMs = 15.0f;
	int shortIcpIterations = 5;
	// and renders the model once a round, not every iteration
	// (IcpConfig::renderOnce): a round ~0.45 -> ~0.35 ms at 10 ms, more
	// rounds and searches; with more time the render each iteration is
	// the more precise.
	bool shortIcpRenderOnce = true;
	// and scores occluded pixels with this weight instead of
	// score.occludedWeight (negative: as that): offline the lower 0.1 gains,
	// at 10 ms, with few and mostly unpolished candidates, it lost 0.02
	// mean F1.
	float shortOccludedWeight = 0.2f;
	// A box's window at most this many pixels (0: EstimatorLimits::
	// maxWindowPixels); a larger box is processed downsampled, as at the
	// limit. Inside a budget the budget one: the render, score and polish
	// of a near or large object grow with its pixels.
	int windowPixels = 0;
	int budgetWindowPixels = 4000;
	// A stage that can be cut runs only if its average cost plus this many
	// mean deviations fits (stage_timer.h): the average alone is exceeded
	// about half the time, and the box then overruns (1 cuts the overruns
	// by 2/3 for ~0.015 mean F1).
	float budgetMargin = 1.0f;
	// The polish and the half-turns (renders and ICP on the crop) are
	// predicted per depth pixel of the box, scaled to each box: the
	// warm-up's box is the largest, and its cost taken as is kept the
	// polish out of every small box that followed. false: their last
	// costs as they are.
	bool budgetScaleByBox = true;
};

// The settings a box runs with inside a frame budget; and inside a tight
// one (a share shorter than budgetTightMs), applied to underBudget()'s.
EstimatorConfig underBudget(EstimatorConfig c);
EstimatorConfig underTightBudget(EstimatorConfig c);
// and inside a short one (shorter than budgetShortMs), applied to those.
EstimatorConfig underShortBudget(EstimatorConfig c);
// The settings a refinement iteration votes with (the iteration* bounds);
// and the bounds lifted, so that iterations vote as the registration does.
EstimatorConfig forIterations(EstimatorConfig c);
void iterationsAsRegistration(EstimatorConfig &c);
// Whether a box with shareMs of its frame left (the frame itself for a
// frame's only box) runs the tight profile.
inline bool tightShare(const EstimatorConfig &c, double shareMs)
{
	return shareMs < static_cast<double>(c.budgetTightMs);
}
inline bool shortShare(const EstimatorConfig &c, double shareMs)
{
	return shareMs < static_cast<double>(c.budgetShortMs);
}

// The settings of a box with shareMs of its frame left: underBudget()'s,
// then the tight and the short profile's where the share is under their
// thresholds (which of them applied, for the stats).
struct ShareSettings {
	EstimatorConfig config;
	bool tight = false;
	bool shortRounds = false;
};
ShareSettings underShare(const EstimatorConfig &c, double shareMs);

} // namespace ihf
