// SPDX-License-Identifier: MIT
// The keys of the three configurations (config_schema.h): one line each,
// read by the loaders (pipeline_config.cpp), printed by `ihf config` and
// documented in docs/configuration.md. Defaults are the settings structs'.

#include "firmware_app/config/config_ops.h"
#include "firmware_app/config/pipeline_config.h"

namespace ihf::app {

namespace {

constexpr Audience U = Audience::kUser, X = Audience::kExpert, SITE = Audience::kSite;

#define IHF_KEY(S, table, name, member, range, who, meaning)                                              \
	KeyDesc                                                                                            \
	{                                                                                                  \
		table, name, [](void *s) { return field(static_cast<S *>(s)->member); }, range, who, meaning \
	}
#define IHF_NAMED(S, table, name, member, names, who, meaning)                                                   \
	KeyDesc                                                                                                   \
	{                                                                                                         \
		table, name, [](void *s) { return field(static_cast<S *>(s)->member, std::span<const Named>(names)); }, \
			kAny, who, meaning                                                                        \
	}

// ---- estimate (ihf estimate, ihf run's estimator) ----

#define E(table, name, member, range, who, meaning) IHF_KEY(EstimateSettings, table, name, member, range, who, meaning)

constexpr Named kBoxKinds[] = {{"amodal", static_cast<int>(BoxKind::kAmodal)}, {"modal", static_cast<int>(BoxKind::kModal)}};

const KeyDesc kEstimateKeys[] = {
	E("refinement", "iterations", estimator.iterations, atLeast(0), U,
	  "k: refinement iterations after the initial registration (the paper's k = 5)"),
	E("refinement", "psi1", estimator.psi1, above(0), X,
	  "Eq. 10: a refinement's crop keeps depths above psi1 times its hypothesis' nearest depth"),
	E("refinement", "psi2", estimator.psi2, above(0), X,
	  "Eq. 10: and below psi2 times its farthest (psi2 >= psi1)"),
	E("refinement", "min_valid_pixels", estimator.minValidPixels, atLeast(0), X,
	  "a box (or a slab of it) with fewer depth pixels than this gives no pose (no votes)"),
	E("refinement", "part_stride", estimator.partStride, atLeast(0), X,
	  "pixels between part centres (0: the forest's training stride)"),
	E("refinement", "target_parts", estimator.targetParts, atLeast(0), X,
	  "a box that would give more parts than this is sampled with a wider stride (0: never)"),
	E("refinement", "depth_windows", estimator.depthWindows, within(0, 8), U,
	  "the initial registration votes on this many densest depth slabs of the box (0: the whole box, as the paper)"),
	E("refinement", "depth_window_width", estimator.depthWindowWidth, above(0), X,
	  "a depth slab's thickness, in object diameters"),
	E("refinement", "hypothesis_cube", estimator.hypothesisCube, kAny, X,
	  "refinement normalises with the unit cube of the whole rendered hypothesis, as training does with the whole "
	  "silhouette (false: the paper's masked cloud)"),
	E("refinement", "ibs_max_points", estimator.ibsMaxPoints, atLeast(0), X,
	  "the IBS fit of a box from at most this many depth points (0: the forest's [ibs] max_points)"),
	E("refinement", "ibs_cg_iterations", estimator.ibsCgIterations, atLeast(0), X,
	  "and with at most this many CG iterations (0: the forest's [ibs] cg_max_iterations)"),
	E("refinement", "research_rounds", estimator.researchRounds, atLeast(0), U,
	  "refinement also searches the view templates again at the polished best's own translation, while a round "
	  "improves the best, at most this many rounds and k (0: off)"),
	E("refinement", "research_polish", estimator.researchPolish, within(0, kMaxViewKeep), X,
	  "proposals of a re-search round that are polished"),

	E("votes", "max_hypotheses", estimator.maxHypotheses, atLeast(1), X,
	  "translation modes scored by rendering, per iteration"),
	E("votes", "rotation_modes", estimator.rotationModes, within(1, 16), X,
	  "rotation modes per translation mode (the paper: 1, the argmax)"),
	E("votes", "translation_bandwidth", estimator.translationBandwidth, above(0), X,
	  "translation mean shift bandwidth, in object diameters"),
	E("votes", "rotation_bandwidth_deg", estimator.rotationBandwidthDeg, above(0), X,
	  "rotation mode bandwidth (degrees)"),
	E("votes", "max_shift_votes", estimator.maxShiftVotes, atLeast(0), X,
	  "the translation mean shift on an even stride of at most this many votes (0: all)"),

	IHF_NAMED(EstimateSettings, "boxes", "kind", boxKind, kBoxKinds, U,
		  "what the given boxes bound: \"amodal\", the whole object with its hidden parts (BOP's bbox_obj), or "
		  "\"modal\", its visible part (bbox_visib, what most detectors give); selects the occlusion and box "
		  "weights ([score]'s or [modal_boxes.score]'s)"),

	E("score", "inlier_mm", estimator.score.inlierMm, above(0), U,
	  "a rendered pixel within this depth of the observed one is an inlier"),
	E("score", "outlier_weight", estimator.score.outlierWeight, atLeast(0), U,
	  "depth score = in / (in + w_out out + w_occ occluded); out: the scene seen through the model"),
	E("score", "occluded_weight", amodal.occludedWeight, atLeast(0), U,
	  "w_occ for amodal boxes: heavier weights lose occluded objects to poses laid on the occluder"),
	E("score", "box_weight", amodal.boxWeight, atLeast(0), U,
	  "the agreement with the given amodal box, raised to this power, scales the score (0: off)"),
	E("score", "box_occluded_side", amodal.boxOccludedSide, within(0, 1), X,
	  "for amodal boxes: a box side where this share of the rendering's edge band is hidden by the scene is open "
	  "to overhang (0: off)"),
	E("score", "box_occluded_band_px", estimator.score.boxOccludedBandPx, atLeast(1), X,
	  "the width of that edge band (pixels)"),
	E("score", "box_min_fill", estimator.score.boxMinFill, within(0, 1), X,
	  "a hypothesis covering less than this share of the box loses (the box factor's fill term)"),
	E("score", "box_margin", estimator.score.boxMargin, atLeast(0), X,
	  "overhang beyond the box tolerated, as a share of its size"),
	E("score", "residual_weight", estimator.score.residualWeight, within(0, 1), X,
	  "an inlier counts 1 - w (e / inlier_mm)^2, here and in the view search (0: each counts 1)"),
	E("score", "skip_edge_outliers", estimator.score.skipEdgeOutliers, kAny, X,
	  "an outlier on the rendering's outline does not count: sensors' edges wander by a pixel or float between "
	  "surfaces"),
	E("score", "edge_share", estimator.score.edgeShare, within(0, 1), X,
	  "the score is scaled by min(1, b / this), b the share of the pose's visible outline where the scene drops "
	  "away outside it: a pose laid on a surface that goes on past its outline (an occluder's face) loses (0: off)"),

	E("icp", "enabled", estimator.icp, kAny, U, "polish the best hypotheses with ICP (not in the paper)"),
	E("icp", "candidates", estimator.icpCandidates, atLeast(0), U,
	  "distinct best hypotheses polished; the best polished one wins"),
	E("icp", "forest_bests", estimator.polishForestBests, kAny, X,
	  "after a refinement also polish the forest's best of the registration and of the last iteration when the "
	  "ranking leaves them out"),
	E("icp", "registration_candidates", estimator.polishRegistration, kAny, X,
	  "after a refinement also polish the registration's and view search's best candidates that the refinement's "
	  "modes pushed out of the ranking"),
	E("icp", "iterations", estimator.icpConfig.iterations, atLeast(0), U, "ICP iterations a round"),
	E("icp", "max_distance_mm", estimator.icpConfig.maxDistanceMm, above(0), U,
	  "the first iteration's correspondence gate"),
	E("icp", "min_distance_mm", estimator.icpConfig.minDistanceMm, above(0), U,
	  "the last iteration's gate (narrowed from max_distance_mm)"),
	E("icp", "render_once", estimator.icpConfig.renderOnce, kAny, X,
	  "render the model once a round and follow it by the pose change, not once an iteration: cheaper, less "
	  "precise"),

	E("view_search", "inplane", estimator.views.inplane, within(0, kMaxInplane), U,
	  "rotation proposals from sparse view templates: in-plane turns per viewpoint (0: off; not in the paper, "
	  "whose rotation votes are weak)"),
	E("view_search", "viewpoints", viewTemplates.viewpoints, within(1, 100000), U,
	  "template directions (a Fibonacci sphere) built at load for forests without templates"),
	E("view_search", "points", viewTemplates.pointsPerView, within(8, kMaxViewPoints), X,
	  "model points per template direction"),
	E("view_search", "centres", estimator.views.centres, within(1, 4), X,
	  "distinct best voted translations searched"),
	E("view_search", "depth_centres", estimator.views.depthCentres, within(0, 4), X,
	  "also search on the box's ray at the median depth of this many densest depth slabs: the votes miss the "
	  "translation of some occluded boxes"),
	E("view_search", "anchor_share", estimator.views.anchorShare, (Range{0, 1, true}), X,
	  "that median over this middle share of the box (its rim is table or wall)"),
	E("view_search", "depth_centre_width", estimator.views.depthCentreWidth, within(0, 10), X,
	  "also the medians of slabs this thick (diameters) in front of those: a near object and the wall behind it "
	  "share a thicker slab (0: off)"),
	E("view_search", "depth_first", estimator.views.depthFirst, kAny, X,
	  "search the depth centres before the voted one"),
	E("view_search", "lateral_step_mm", estimator.views.lateralStepMm, atLeast(0), X,
	  "the best rotations climb the sparse score sideways in steps of this, then half, then a quarter (0: off)"),
	E("view_search", "rotation_step_deg", estimator.views.rotationStepDeg, within(0, 45), X,
	  "and turn about the camera axes by this, half and a quarter: the template grid is coarse (0: off)"),
	E("view_search", "refine_top", estimator.views.refineTop, within(1, kMaxRefineTop), X,
	  "rotations that climb"),
	E("view_search", "keep", estimator.views.keep, within(1, kMaxViewKeep), X,
	  "proposals per searched translation, scored in full and polished"),
	E("view_search", "inlier_mm", estimator.views.inlierMm, above(0), X, "the sparse score's inlier distance"),
	E("view_search", "max_shift_mm", estimator.views.maxShiftMm, atLeast(0), X,
	  "depth alignment range of a placed rotation"),
	E("view_search", "distinct_deg", estimator.views.distinctDeg, atLeast(0), X,
	  "proposals closer than this in rotation count once"),
	E("view_search", "box_centre", estimator.views.boxCentre, kAny, X,
	  "also try the translation that centres a rotation in the box (on an axis the frame clipped, against its "
	  "other side)"),
	E("view_search", "edge_insets", estimator.views.edgeInsets, within(0, 8), X,
	  "on an axis clipped on one side also place the extent this many times further inside the other side"),
	E("view_search", "edge_inset_share", estimator.views.edgeInsetShare, within(0, 0.5), X,
	  "each inset this share of the box's size: a box drawn with a margin"),
	E("view_search", "centre_shift_share", estimator.views.centreShiftShare, within(0, 0.5), X,
	  "also the box-centred placement shifted by this share of the extent to either side (0: centred only)"),
	E("view_search", "box_size_search", amodal.boxSizeSearch, kAny, X,
	  "an amodal box not cut by the frame is searched once more with each rotation at the depth where it fills "
	  "the box (never for modal boxes)"),
	E("view_search", "coarse_points", estimator.views.coarsePoints, within(0, kMaxViewPoints), X,
	  "a first pass scores every rotation on this many points per view (0: one pass on all)"),
	E("view_search", "coarse_keep", estimator.views.coarseKeep, within(1, kMaxCoarseKeep), X,
	  "rotations the first pass keeps for the full score"),
	E("view_search", "coarse_at_centre", estimator.views.coarseAtCentre, kAny, X,
	  "the coarse pass of a depth centre scores each rotation box-centred only, the fine pass both"),

	E("half_turns", "candidates", estimator.halfTurns.candidates, within(0, 4), U,
	  "distinct best polished hypotheses turned by 180 deg, scored and the best turns polished (0: off): a view "
	  "and its half-turn often look alike"),
	E("half_turns", "axes", estimator.halfTurns.axes, within(0, 1024), X,
	  "turn axes spread over a hemisphere of the model frame"),
	E("half_turns", "keep", estimator.halfTurns.keep, within(1, kMaxHalfTurnKeep), X,
	  "best turns per hypothesis polished"),
	E("half_turns", "align", estimator.halfTurns.align, kAny, X,
	  "move each turn so the surface it shows sits where the hypothesis' did"),
	E("half_turns", "screen", estimator.halfTurns.screen, within(0, kMaxHalfTurnScreen), X,
	  "turns placed and scored on their nearest view templates, only this many best rendered (0: render every "
	  "turn)"),
	E("half_turns", "box_axes", estimator.halfTurns.boxAxes, kAny, X,
	  "also the exact turns about the model's own x, y and z axes"),

	E("symmetry_turns", "enabled", estimator.symmetryTurns.enabled, kAny, U,
	  "a nearly symmetric object's pose compared with its turns about the axes training found, on the pixels "
	  "where they differ; the pose is flagged ambiguous when the depth cannot tell them apart (not in the paper)"),
	E("symmetry_turns", "polish_rivals", estimator.symmetryTurns.polishRivals, within(0, kMaxSymmetryRivalsPolished),
	  X,
	  "turns the best does not clearly beat, polished before they are compared again (the turn of a pose a little "
	  "off is as far off)"),
	E("symmetry_turns", "close_rivals", estimator.symmetryTurns.closeRivals, within(0, kMaxCloseRivals), X,
	  "the best-scoring hypotheses distinct from the best, compared with it on the pixels where they differ (the "
	  "object upside down and slid along its axis fits the depth it covers as well as the truth)"),
	E("symmetry_turns", "close_loss", estimator.symmetryTurns.closeLoss, within(0, 1), X,
	  "a close rival that wins there replaces the best only if, polished, it scores at most this much less"),

	E("confidence", "distinct_share", estimator.confidence.distinctShare, (Range{0, 1, true}), X,
	  "a rival is a different pose when its model points lie this far on average, in diameters"),
	E("confidence", "full_margin", estimator.confidence.fullMargin, within(0, 1), U,
	  "confidence = score x min(1, margin over the best distinct rival / this) (0: the score alone)"),

	E("render_mesh", "max_error_mm", renderMeshErrorMm, within(0, 20), X,
	  "hypotheses are rendered with the mesh simplified at load while the surface moves by at most this (0: the "
	  "full mesh)"),
	E("render_mesh", "cull_back_faces", estimator.cullBackFaces, kAny, X,
	  "skip the faces turned away when the simplified mesh is closed: the same depth, cheaper"),

	E("limits", "threads", limits.threads, within(0, WorkerPool::kMaxThreads), U,
	  "threads of a box's searches and polish, the caller included (0: one per core, at most 8); poses do not "
	  "depend on it"),
	E("limits", "max_window_pixels", limits.maxWindowPixels, atLeast(1), X,
	  "larger boxes are processed downsampled"),
	E("limits", "max_parts", limits.maxParts, atLeast(1), X, "parts of a box at most"),
	E("limits", "max_part_control_points", limits.maxPartControlPoints, atLeast(1), X,
	  "control points of a part at most"),
	E("limits", "max_votes", limits.maxVotes, atLeast(1), X, "votes of a box at most"),
	E("limits", "max_active", limits.maxActive, atLeast(1), X, "active IBS control points at most"),
	E("limits", "max_ibs_points", limits.maxIbsPoints, atLeast(1), X,
	  "IBS data points at most (grown to the forests')"),
	E("limits", "max_ibs_n", limits.maxIbsN, atLeast(1), X, "IBS lattice size at most (grown to the forests')"),
	E("limits", "max_mesh_vertices", limits.maxMeshVertices, atLeast(1), X,
	  "render mesh vertices at most (grown to the models')"),
	E("limits", "max_histogram_dims", limits.maxHistogramDims, atLeast(1), X,
	  "HoCP length at most (grown to the forests')"),
	E("limits", "max_modes", limits.maxModes, atLeast(1), X, "vote modes per iteration at most"),
	E("limits", "max_mode_seeds", limits.maxModeSeeds, atLeast(1), X, "mean shift seeds at most"),
	E("limits", "max_candidates", limits.maxCandidates, atLeast(1), X,
	  "distinct hypotheses kept over the iterations"),
	E("limits", "max_rivals", limits.maxRivals, atLeast(0), X,
	  "scored hypotheses kept for the confidence's margin"),

	// Inside a frame budget (ihf run; ihf estimate --budget-ms).
	E("budget", "estimation_budget_ms", estimator.frameBudgetMs, atLeast(0), U,
	  "the estimation time of a frame (ms), shared by its boxes; stages that can be cut run only while they fit "
	  "(0: unlimited, the full method)"),
	E("budget", "margin", estimator.budgetMargin, within(0, 10), X,
	  "a stage runs if its average cost plus this many mean deviations fits: the average alone is exceeded about "
	  "half the time"),
	E("budget", "scale_by_box", estimator.budgetScaleByBox, kAny, X,
	  "the polish and half-turns are predicted per depth pixel of the box (false: as last measured)"),
	E("budget", "polish_rounds", estimator.views.budgetPolishRounds, within(0, 16), X,
	  "a view search after the first must leave room for this many ICP rounds (0: search while it fits)"),
	E("budget.refinement", "iterations", estimator.budgetIterations, atLeast(0), X,
	  "at most this many refinement iterations, each only if the searches and the polish still fit after it"),
	E("budget.refinement", "research_rounds", estimator.budgetResearchRounds, atLeast(0), X,
	  "at most this many re-search rounds"),
	E("budget.refinement", "depth_windows", estimator.budgetDepthWindows, atLeast(0), X,
	  "at most this many depth slabs"),
	E("budget.refinement", "target_parts", estimator.budgetTargetParts, atLeast(1), X,
	  "parts near at most this many: a large object's full vote overruns a 33 ms frame"),
	E("budget.refinement", "ibs_max_points", estimator.budgetIbsMaxPoints, atLeast(1), X,
	  "the IBS fit from at most this many points: the votes only place the view search"),
	E("budget.refinement", "ibs_cg_iterations", estimator.budgetIbsCgIterations, atLeast(1), X,
	  "and at most this many CG iterations"),
	E("budget.limits", "max_window_pixels", estimator.budgetWindowPixels, atLeast(1), X,
	  "a box's window at most this many pixels, larger ones downsampled: render, score and polish grow with it"),
	E("budget.view_search", "viewpoints", viewTemplates.budgetViewpoints, within(1, 100000), X,
	  "template directions built at load when the estimator has a frame budget"),
	E("budget.view_search", "rotation_step_deg", estimator.views.budgetRotationStepDeg, within(0, 45), X,
	  "instead of [view_search]'s"),
	E("budget.view_search", "refine_top", estimator.views.budgetRefineTop, within(1, kMaxRefineTop), X,
	  "at most this many rotations climb"),
	E("budget.view_search", "coarse_points", estimator.views.budgetCoarsePoints, within(0, kMaxViewPoints), X,
	  "instead of [view_search]'s: a search that fits a 33 ms frame"),
	E("budget.view_search", "coarse_keep", estimator.views.budgetCoarseKeep, within(1, kMaxCoarseKeep), X,
	  "instead of [view_search]'s"),
	E("budget.view_search", "coarse_shifted", estimator.views.budgetCoarseShifted, within(0, 64), X,
	  "the first pass tries the shifted placements only on the rotations ranking in this many times "
	  "coarse_keep at their others (0: on all, as unbudgeted)"),
	E("budget.view_search", "depth_centres", estimator.views.budgetDepthCentres, within(0, 4), X,
	  "at most this many depth centres"),
	E("budget.view_search", "depth_centre_width", estimator.views.budgetDepthCentreWidth, within(0, 10), X,
	  "instead of [view_search]'s"),
	E("budget.view_search", "depth_first", estimator.views.budgetDepthFirst, kAny, X,
	  "instead of [view_search]'s: where one search fits it should be a depth centre's"),
	E("budget.view_search", "centre_shift_share", estimator.views.budgetCentreShiftShare, within(0, 0.5), X,
	  "instead of [view_search]'s"),

	E("tight", "below_ms", estimator.budgetTightMs, atLeast(0), X,
	  "a box whose share of the frame's budget is shorter than this votes leaner still, with [tight.*] (0: "
	  "never): the full registration leaves a short share no room for the search and the polish"),
	E("tight.refinement", "target_parts", estimator.tightTargetParts, atLeast(1), X, "at most"),
	E("tight.refinement", "ibs_max_points", estimator.tightIbsMaxPoints, atLeast(1), X, "at most"),
	E("tight.refinement", "ibs_cg_iterations", estimator.tightIbsCgIterations, atLeast(1), X, "at most"),
	E("tight.votes", "max_shift_votes", estimator.tightMaxShiftVotes, atLeast(1), X, "at most"),
	E("tight.votes", "max_hypotheses", estimator.tightMaxHypotheses, atLeast(1), X, "at most"),
	E("tight.votes", "rotation_modes", estimator.tightRotationModes, atLeast(1), X, "at most"),
	E("tight.view_search", "centre_shift_share", estimator.tightCentreShiftShare, within(0, 0.5), X,
	  "at most: shifted placements double the search"),

	E("short", "below_ms", estimator.budgetShortMs, atLeast(0), X,
	  "a box whose share is shorter than this polishes with [short.*] (0: never)"),
	E("short.icp", "iterations", estimator.shortIcpIterations, atLeast(1), X,
	  "at most: shorter rounds buy more rounds and searches"),
	E("short.icp", "render_once", estimator.shortIcpRenderOnce, kAny, X,
	  "true: render once a round (false: as [icp])"),
	E("short.score", "occluded_weight", estimator.shortOccludedWeight, atLeast(0), X,
	  "instead of [score]'s: few, mostly unpolished candidates lose to a lower weight"),

	E("lean", "below_searches", estimator.views.leanSearchBelow, within(0, 1000), X,
	  "a box whose share is shorter than this many of the budget's searches (as measured) searches with "
	  "[lean.view_search] (0: never)"),
	E("lean.view_search", "rotation_step_deg", estimator.views.leanRotationStepDeg, within(0, 45), X,
	  "instead of the budget's"),
	E("lean.view_search", "coarse_points", estimator.views.leanCoarsePoints, within(0, kMaxViewPoints), X,
	  "instead of the budget's"),

	E("iteration.refinement", "target_parts", estimator.iterationTargetParts, atLeast(1), X,
	  "a refinement iteration (k > 0) votes leaner than the registration, which must find the object: at most"),
	E("iteration.refinement", "ibs_max_points", estimator.iterationIbsMaxPoints, atLeast(1), X, "at most"),
	E("iteration.refinement", "ibs_cg_iterations", estimator.iterationIbsCgIterations, atLeast(1), X, "at most"),
	E("iteration.votes", "max_shift_votes", estimator.iterationMaxShiftVotes, atLeast(1), X, "at most"),

	E("modal_boxes.score", "occluded_weight", modal.occludedWeight, atLeast(0), U,
	  "w_occ for modal boxes ([boxes] kind = \"modal\")"),
	E("modal_boxes.score", "box_weight", modal.boxWeight, atLeast(0), X, "the box power for modal boxes"),
	E("modal_boxes.score", "box_occluded_side", modal.boxOccludedSide, within(0, 1), X,
	  "for modal boxes: the sides the scene hides are open to overhang"),
};
#undef E

// ---- train (ihf train) ----

#define T(table, name, member, range, who, meaning) IHF_KEY(TrainSettings, table, name, member, range, who, meaning)
#define TN(table, name, member, names, who, meaning) IHF_NAMED(TrainSettings, table, name, member, names, who, meaning)

constexpr Named kSolvers[] = {{"cg", static_cast<int>(IbsSolver::kConjugateGradient)},
			      {"mba", static_cast<int>(IbsSolver::kMultilevelBa)}};
constexpr Named kWarmStarts[] = {{"zero", static_cast<int>(IbsWarmStart::kZero)},
				 {"mba", static_cast<int>(IbsWarmStart::kMultilevelBa)},
				 {"previous", static_cast<int>(IbsWarmStart::kPrevious)}};
constexpr Named kPartKinds[] = {{"variable", static_cast<int>(PartKind::kVariable)},
				{"fixed", static_cast<int>(PartKind::kFixed)}};
constexpr Named kPartCaps[] = {{"uniform", static_cast<int>(PartCap::kUniform)},
			       {"largest_weight", static_cast<int>(PartCap::kLargestWeight)}};
constexpr Named kWeightings[] = {{"count", static_cast<int>(HocpWeighting::kCount)},
				 {"abs_weight", static_cast<int>(HocpWeighting::kAbsWeight)},
				 {"sign_split", static_cast<int>(HocpWeighting::kSignSplit)}};
constexpr Named kObjectives[] = {{"alternate", static_cast<int>(SplitObjective::kAlternate)},
				 {"offset", static_cast<int>(SplitObjective::kOffset)},
				 {"pose", static_cast<int>(SplitObjective::kPose)},
				 {"sum", static_cast<int>(SplitObjective::kSum)}};
constexpr Named kEncodings[] = {{"uint8", static_cast<int>(TemplateEncoding::kUint8)},
				{"float32", static_cast<int>(TemplateEncoding::kFloat32)}};

const KeyDesc kTrainKeys[] = {
	T("views", "viewpoints", set.views.viewpoints, atLeast(1), U,
	  "training directions over the whole view sphere (a Fibonacci lattice)"),
	T("views", "inplane_steps", set.views.inplaneSteps, atLeast(1), U, "in-plane rotations per direction"),
	T("views", "min_elevation_deg", set.views.minElevationDeg, within(-90, 90), X,
	  "lowest camera elevation over the model's xy plane"),
	T("views", "max_elevation_deg", set.views.maxElevationDeg, within(-90, 90), X, "highest camera elevation"),
	T("views", "min_distance_mm", set.views.minDistance, above(0), U,
	  "camera to object distance, from (the paper: one distance, 750 mm)"),
	T("views", "max_distance_mm", set.views.maxDistance, above(0), U, "to"),
	T("scales", "factors", set.scales, kAny, U, "part scales s_i >= 1 (the paper: nine)"),
	T("scales", "parts_per_image", set.partsPerImage, atLeast(1), X, "part centres drawn per view and scale"),
	T("scales", "occluded_views", set.occludedViews, within(0, 1), X,
	  "share of views with a random side cut away (the paper: clean views only)"),
	T("scales", "occlusion_min", set.occlusionMin, within(0, 1), X, "share of the silhouette cut away, from"),
	T("scales", "occlusion_max", set.occlusionMax, within(0, 1), X, "to"),
	T("cloud", "normal_step", params.cloud.normalStep, atLeast(1), X, "pixels between the differenced neighbours"),
	T("cloud", "max_jump_mm", params.cloud.maxJumpMm, atLeast(0), X,
	  "neighbours further apart in depth than this (or max_jump_rel of the depth) give no normal"),
	T("cloud", "max_jump_rel", params.cloud.maxJumpRel, atLeast(0), X, "the relative depth jump"),
	T("cloud", "pixel_stride", params.cloud.pixelStride, atLeast(1), X, "every k-th pixel in x and y"),
	T("ibs", "n", params.ibs.n, atLeast(2), U, "IBS lattice nodes per axis (the paper: 50 to 100)"),
	TN("ibs", "solver", params.ibs.solver, kSolvers, X,
	   "\"cg\" (3L least squares, bounded CG) or \"mba\" (multilevel B-spline approximation)"),
	T("ibs", "offset_cells", params.ibs.offsetCells, kAny, X, "3L offset epsilon, in lattice cells"),
	T("ibs", "offset_value", params.ibs.offsetValue, kAny, X, "3L value c at p +- epsilon n"),
	T("ibs", "max_points", params.ibs.maxPoints, atLeast(1), X, "data points used (uniform subsample)"),
	TN("ibs", "warm_start", params.ibs.warmStart, kWarmStarts, X, "CG's start"),
	T("ibs", "cg_max_iterations", params.ibs.cgMaxIterations, atLeast(1), X, "CG iterations at most"),
	T("ibs", "cg_tolerance", params.ibs.cgTolerance, atLeast(0), X, "CG stops at |r| <= tol |b|"),
	T("ibs", "smoothness", params.ibs.smoothness, atLeast(0), X, "the fit's smoothness weight"),
	T("ibs", "ridge", params.ibs.ridge, atLeast(0), X, "the fit's ridge weight"),
	T("ibs", "mba_levels", params.ibs.mbaLevels, atLeast(1), X, "multilevel B-spline levels"),
	TN("parts", "kind", params.parts.kind, kPartKinds, U,
	   "\"fixed\" (IHF-fixed size: windows of the cloud's image box) or \"variable\" (cubes of fixed side)"),
	T("parts", "stride", params.parts.stride, atLeast(1), U, "pixels between part centres"),
	T("parts", "fixed_fraction", params.parts.fixedFraction, above(0), X, "g^0 of fixed parts (the paper: 1/2)"),
	T("parts", "variable_side", params.parts.variableSide, above(0), X,
	  "cube side of variable parts in the unit cube (the paper: 3/4)"),
	T("parts", "depth_margin_cells", params.parts.depthMarginCells, atLeast(0), X,
	  "control points kept within this many cells of the data's depth"),
	T("parts", "max_control_points", params.parts.maxControlPoints, atLeast(1), X, "per part, after the depth limit"),
	TN("parts", "cap", params.parts.cap, kPartCaps, X, "which control points a full part keeps"),
	T("parts", "min_data_points", params.parts.minDataPoints, atLeast(0), X, "sparser parts are skipped"),
	T("hocp", "n_r", params.hocp.nR, kAny, X, "radial bins (n_r x n_theta x n_phi: the descriptor's length)"),
	T("hocp", "n_theta", params.hocp.nTheta, kAny, X, "polar bins"),
	T("hocp", "n_phi", params.hocp.nPhi, kAny, X, "azimuthal bins"),
	T("hocp", "r_min_fraction", params.hocp.rMinFraction, kAny, X, "the first radial bin's edge, of r_max"),
	TN("hocp", "weighting", params.hocp.weighting, kWeightings, X, "what a control point adds (the paper: one)"),
	T("forest", "trees", forest.trees, atLeast(1), U, "trees (the paper: 3)"),
	T("forest", "max_depth", forest.maxDepth, atLeast(1), U, "tree depth at most (the paper: 25)"),
	T("forest", "max_leaf_samples", forest.maxLeafSamples, atLeast(1), X,
	  "a node with this many samples or fewer is a leaf (the paper: 15)"),
	T("forest", "templates_per_node", forest.templatesPerNode, atLeast(1), X, "candidate template parts per split"),
	T("forest", "sample_fraction", forest.sampleFraction, (Range{0, 1, true}), X, "bootstrap share of the samples per tree"),
	TN("forest", "objective", forest.objective, kObjectives, X,
	   "the split's entropy: offset or pose at random per node (alternate), either, or their sum"),
	T("forest", "depth_check_margin_mm", params.depthCheckMarginMm, atLeast(0), X, "the depth check's margin"),
	TN("forest", "encoding", encoding, kEncodings, X, "templates in the forest file: quantised or float"),
	T("forest", "seed", forest.seed, kAny, U, "the seed of views, samples and trees"),
	T("forest", "threads", forest.threads, atLeast(0), U, "training threads"),
};
#undef T
#undef TN

// ---- device (ihf run) ----

#define D(table, name, member, range, who, meaning) IHF_KEY(RunSettings, table, name, member, range, who, meaning)

constexpr Named kPacing[] = {{"step", 0}, {"real_time", 1}};
constexpr Named kRunBoxKinds[] = {{"", -1},
				  {"amodal", static_cast<int>(BoxKind::kAmodal)},
				  {"modal", static_cast<int>(BoxKind::kModal)}};

const KeyDesc kDeviceKeys[] = {
	D("source", "uri", sourceUri, kAny, SITE,
	  "the depth source: \"recording:PATH\", \"v4l2:/dev/videoN?...\", \"openni2:\" (ihf devices lists them)"),
	IHF_NAMED(RunSettings, "source", "pacing", realTime, kPacing, U,
		  "recordings: \"step\" (every frame) or \"real_time\" (paced by their timestamps, late frames dropped)"),
	D("source", "speed", speed, above(0), X, "real-time replay speed"),
	D("source", "timeout_ms", timeoutMs, above(0), X, "a live source silent this long is reported"),
	D("source", "max_retries", maxRetries, atLeast(0), X, "reopen attempts in a row after a source error"),
	D("source", "retry_backoff_ms", retryBackoffMs, atLeast(0), X, "wait before the first reopen, doubled each time"),
	D("source", "retry_backoff_max_ms", retryBackoffMaxMs, atLeast(0), X,
	  "the longest wait (at least retry_backoff_ms)"),
	D("source", "usb_watch", usbWatch, kAny, U,
	  "\"any\" known depth sensor or \"VID:PID\": report unplugs and wait for the sensor (\"\": off)"),
	D("boxes", "input", boxes, kAny, SITE, "the detector's boxes: \"stdin\", \"file:PATH\" or \"unix:PATH\""),
	D("boxes", "timeout_ms", boxesTimeoutMs, atLeast(0), X, "live inputs: how long to wait for a frame's boxes"),
	IHF_NAMED(RunSettings, "boxes", "kind", boxKind, kRunBoxKinds, U,
		  "\"amodal\" or \"modal\" ([boxes] kind of the estimation config); \"\": as the estimation config"),
	D("output", "poses", poses, kAny, SITE, "\"stdout\", \"file:PATH\" or \"socket\" (back on the boxes' socket)"),
	D("estimate", "config", estimateConfig, kAny, SITE, "the estimation config (\"\": the defaults)"),
	D("estimate", "iterations", iterations, atLeast(0), X, "k, instead of the estimation config's (unset: its)"),
	D("estimate", "estimation_budget_ms", estimationBudgetMs, atLeast(0), SITE,
	  "the estimation time of a frame (ms), shared by its boxes, tracked ones first (0: unlimited; unset: the "
	  "estimation config's, or 33 ms without one); the sensor's frame period"),
	D("tracking", "enabled", tracking.enabled, kAny, U,
	  "follow each object from frame to frame (false: every box a cold detection)"),
	D("tracking", "match_iou", tracking.matchIou, (Range{0, 1, true}), X, "a box belongs to a track when it overlaps the track's predicted silhouette by this IoU"),
	D("tracking", "max_missed_frames", tracking.maxMissedFrames, atLeast(1), X,
	  "a track with no box for this many frames in a row ends"),
	D("tracking", "max_defer_frames", tracking.maxDeferFrames, atLeast(1), X,
	  "a box waits at most this many frames for its detection"),
	D("tracking", "detect_min_ms", tracking.detectMinMs, atLeast(0), X,
	  "a detection runs only with this much of the frame left (unless due)"),
	D("tracking", "refresh", tracking.refresh, kAny, X, "time a budgeted frame has left goes to detecting tracked boxes again (an unbudgeted frame: its ambiguous tracks); a better detection replaces the tracked pose, one that tells apart the turns an ambiguous track could not settles it"),
	D("tracking", "min_score", tracking.minScore, within(0, 1), X, "a tracked pose is kept only if it scores at least this"),
	D("tracking", "keep_share", tracking.keepShare, within(0, 1), X,
	  "and at least this share of its detection's score"),
	D("run", "drop_frames_older_than_ms", dropFramesOlderThanMs, atLeast(0), U,
	  "real time: frames older than this when their turn comes are dropped and counted (0: never)"),
	D("run", "stats_interval_s", statsIntervalS, atLeast(0), U, "stats on stderr (0: only at the end)"),
	D("run", "max_frames", maxFrames, atLeast(0), X, "stop after this many frames (0: at the stream's end or a signal)"),
};
#undef D

const char *const kDeviceFreeTables[] = {"objects"};
const KeyDesc kDeviceFreeKeys[] = {
	KeyDesc{"objects", "<id>", nullptr, kAny, SITE, "an object id and its forest file (\"20\" = \"bunny.ihf\")"},
};

const TableNote kEstimateNotes[] = {
	{"refinement", "The iterative registration: the initial registration votes on the box, then k refinement "
		       "iterations vote on crops cut to their hypotheses' depth (the paper's method)."},
	{"votes", "Vote modes: translation by mean shift, rotation modes per translation."},
	{"boxes", "What the given boxes bound."},
	{"score", "The depth score of a rendered hypothesis against the observed depth, with the weights for amodal "
		  "boxes."},
	{"icp", "The polish: projective ICP on the crop cut to the hypothesis' depth range (not in the paper)."},
	{"view_search", "Rotation proposals from sparse view templates, checked at the best voted translations and at "
			"centres from the box's depth (not in the paper): the forest's translation votes are good, "
			"its rotation votes weak."},
	{"half_turns", "The best polished hypotheses turned by 180 deg about axes through the model's centre (not in "
		       "the paper)."},
	{"confidence", "The pose's confidence (the CSV's score): less when a distinct rival scored nearly as well."},
	{"render_mesh", "The mesh hypotheses are rendered with (training and the view templates use the full mesh)."},
	{"limits", "Capacities of the estimator's arena, allocated once at start-up."},
	{"budget", "Inside a frame budget (ihf run; ihf estimate --budget-ms): a frame's boxes share its time and a "
		   "stage that can be cut runs only while its predicted cost fits. [budget.*] override the base tables "
		   "inside a budget."},
	{"tight", "A box with a short share of the frame's budget votes leaner still: [tight.*] override the budget's "
		  "settings."},
	{"short", "A box with a shorter share still polishes with shorter rounds: [short.*] override the budget's "
		  "settings."},
	{"lean", "A box whose share fits only a few view searches searches leaner: [lean.view_search] overrides the "
		 "budget's search."},
	{"iteration", "Refinement iterations (k > 0): [iteration.*] override the base tables in them."},
	{"modal_boxes", "Boxes round the visible part ([boxes] kind = \"modal\"): [modal_boxes.score] overrides "
			"[score]."},
};

const TableNote kTrainNotes[] = {
	{"views", "The training views: camera directions, in-plane turns and distances."},
	{"scales", "Part scales and the views' synthetic occlusion."},
	{"cloud", "Depth to point cloud with normals."},
	{"ibs", "The implicit B-spline fit of a part's points (3L)."},
	{"parts", "Parts: where they are cut and how large."},
	{"hocp", "The HoCP descriptor of a part (histogram of control points)."},
	{"forest", "The Hough forest."},
};

const TableNote kDeviceNotes[] = {
	{"source", "The depth source."},
	{"boxes", "The detector's boxes."},
	{"output", "Where the poses go (JSON lines)."},
	{"objects", "Object id = forest file, one per object."},
	{"estimate", "The estimation config and what ihf run overrides in it."},
	{"tracking", "Frame-to-frame tracking."},
	{"run", "The loop."},
};

template<typename S>
void *make()
{
	return new S();
}
template<typename S>
void destroy(void *p)
{
	delete static_cast<S *>(p);
}

template<typename S, Expected<S> (*Load)(const std::filesystem::path &)>
Status load(const std::filesystem::path &path, void *settings)
{
	Expected<S> s = Load(path);
	if (!s)
		return s.error();
	*static_cast<S *>(settings) = std::move(*s);
	return {};
}

} // namespace

const Schema &estimateSchema()
{
	static const Schema s{"estimate", "config/estimate.toml", "`ihf estimate --config FILE` and `ihf run` (its [estimate] config)",
			      kEstimateKeys, {}, {}, kEstimateNotes, &make<EstimateSettings>, &destroy<EstimateSettings>,
			      &load<EstimateSettings, &loadEstimateConfig>};
	return s;
}

const Schema &trainSchema()
{
	static const Schema s{"train", "config/train.toml", "`ihf train --config FILE`", kTrainKeys, {}, {}, kTrainNotes,
			      &make<TrainSettings>, &destroy<TrainSettings>,
			      &load<TrainSettings, &loadTrainConfig>};
	return s;
}

const Schema &deviceSchema()
{
	static const Schema s{"device", "config/device.toml", "`ihf run --config FILE`", kDeviceKeys, kDeviceFreeTables,
			      kDeviceFreeKeys, kDeviceNotes, &make<RunSettings>, &destroy<RunSettings>,
			      &load<RunSettings, &loadRunConfig>};
	return s;
}

} // namespace ihf::app
