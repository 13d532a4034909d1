// SPDX-License-Identifier: MIT
#include "firmware_app/pipeline_config.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <set>
#include <string>

#include <toml++/toml.h>

#include "core/geometry/mesh_simplify.h"

namespace ihf::app {

namespace {

// Reads keys of one table, remembering which were seen so that leftovers
// can be reported as unknown.
class TableReader
{
public:
	TableReader(const toml::table *table, std::string file, std::string section)
		: table_(table), file_(std::move(file)), section_(std::move(section)) {}

	template<typename T>
	void get(const char *key, T &out)
	{
		seen_.insert(key);
		if (!table_ || failed())
			return;
		const toml::node *node = table_->get(key);
		if (!node)
			return;
		if constexpr (std::is_same_v<T, bool>) {
			if (auto v = node->value_exact<bool>())
				out = *v;
			else
				fail(key, "a boolean");
		} else if constexpr (std::is_integral_v<T>) {
			// TOML integers are 64-bit: a value the setting's type cannot
			// hold is an error, never wrapped into range.
			if (auto v = node->value_exact<int64_t>()) {
				if (std::in_range<T>(*v))
					out = static_cast<T>(*v);
				else
					outOfRange(key, std::to_string(*v) + " is out of range [" +
								std::to_string(std::numeric_limits<T>::min()) + ", " +
								std::to_string(std::numeric_limits<T>::max()) + "]");
			} else {
				fail(key, "an integer");
			}
		} else if constexpr (std::is_floating_point_v<T>) {
			if (auto v = node->value<double>()) {
				if (std::isfinite(*v) && std::abs(*v) > std::numeric_limits<T>::max())
					outOfRange(key, std::to_string(*v) + " is outside the range of a " +
								std::to_string(8 * sizeof(T)) + "-bit float");
				else
					out = static_cast<T>(*v);
			} else {
				fail(key, "a number");
			}
		} else if constexpr (std::is_same_v<T, std::string>) {
			if (auto v = node->value_exact<std::string>())
				out = *v;
			else
				fail(key, "a string");
		} else if constexpr (std::is_same_v<T, std::vector<float>>) {
			const toml::array *arr = node->as_array();
			if (!arr) {
				fail(key, "an array of numbers");
				return;
			}
			out.clear();
			for (const auto &el : *arr) {
				auto v = el.value<double>();
				if (!v) {
					fail(key, "an array of numbers");
					return;
				}
				out.push_back(static_cast<float>(*v));
			}
		}
	}

	// A string key mapped through a list of (name, value) pairs.
	template<typename E>
	void getEnum(const char *key, E &out, std::initializer_list<std::pair<const char *, E>> names)
	{
		std::string s;
		bool present = table_ && table_->get(key);
		get(key, s);
		if (!present || failed())
			return;
		for (const auto &[name, value] : names)
			if (s == name) {
				out = value;
				return;
			}
		std::string allowed;
		for (const auto &[name, value] : names)
			allowed += std::string(allowed.empty() ? "" : ", ") + name;
		error_ = makeError(Errc::kParse, file_ + ": " + section_ + "." + key + ": unknown value \"" +
							 s + "\" (allowed: " + allowed + ")");
	}

	// Call after all get()s: flags keys nobody asked for.
	void finish()
	{
		if (!table_ || failed())
			return;
		for (const auto &[k, v] : *table_)
			if (!seen_.count(std::string(k.str()))) {
				error_ = makeError(Errc::kParse, file_ + ": unknown key " + section_ + "." +
									 std::string(k.str()));
				return;
			}
	}

	bool failed() const { return error_.has_value(); }
	const Error &error() const { return *error_; }

private:
	void fail(const char *key, const char *what)
	{
		error_ = makeError(Errc::kParse, file_ + ": " + section_ + "." + key + ": expected " + what);
	}
	void outOfRange(const char *key, const std::string &what)
	{
		error_ = makeError(Errc::kOutOfRange, file_ + ": " + section_ + "." + key + ": " + what);
	}

	const toml::table *table_;
	std::string file_, section_;
	std::set<std::string> seen_;
	std::optional<Error> error_;
};

Expected<toml::table> parseFile(const std::filesystem::path &path)
{
	try {
		return toml::parse_file(path.string());
	} catch (const toml::parse_error &e) {
		const auto &where = e.source().begin;
		return makeError(Errc::kParse, path.string() + ":" + std::to_string(where.line) + ":" +
						       std::to_string(where.column) + ": " +
						       std::string(e.description()));
	}
}

Status checkSections(const toml::table &root, const std::string &file,
		     std::initializer_list<const char *> known)
{
	for (const auto &[k, v] : root) {
		bool ok = false;
		for (const char *name : known)
			ok = ok || k.str() == name;
		if (!ok)
			return makeError(Errc::kParse, file + ": unknown section [" + std::string(k.str()) + "]");
		if (!v.is_table())
			return makeError(Errc::kParse, file + ": " + std::string(k.str()) + " must be a table");
	}
	return {};
}

// Parses a configuration file and checks its sections against `known`.
Expected<toml::table> openConfig(const std::filesystem::path &path,
				 std::initializer_list<const char *> known)
{
	auto parsed = parseFile(path);
	if (!parsed)
		return parsed.error();
	if (auto st = checkSections(*parsed, path.string(), known); !st)
		return st.error();
	return parsed;
}

#define IHF_SECTION(reader)            \
	do {                           \
		(reader).finish();     \
		if ((reader).failed()) \
			return (reader).error(); \
	} while (0)

// "FILE: KEY: out of range" unless ok.
Status rangeCheck(bool ok, const std::string &file, const char *key)
{
	if (ok)
		return {};
	return makeError(Errc::kParse, file + ": " + key + ": out of range");
}

} // namespace

Expected<TrainSettings> loadTrainConfig(const std::filesystem::path &path)
{
	TrainSettings s;
	if (path.empty())
		return s;
	auto parsed = openConfig(path, {"views", "scales", "cloud", "ibs", "parts", "hocp", "forest"});
	if (!parsed)
		return parsed.error();
	const toml::table &root = *parsed;
	const std::string file = path.string();

	TableReader views(root["views"].as_table(), file, "views");
	views.get("viewpoints", s.set.views.viewpoints);
	views.get("inplane_steps", s.set.views.inplaneSteps);
	views.get("min_elevation_deg", s.set.views.minElevationDeg);
	views.get("max_elevation_deg", s.set.views.maxElevationDeg);
	views.get("min_distance_mm", s.set.views.minDistance);
	views.get("max_distance_mm", s.set.views.maxDistance);
	IHF_SECTION(views);

	TableReader scales(root["scales"].as_table(), file, "scales");
	scales.get("factors", s.set.scales);
	scales.get("parts_per_image", s.set.partsPerImage);
	scales.get("occluded_views", s.set.occludedViews);
	scales.get("occlusion_min", s.set.occlusionMin);
	scales.get("occlusion_max", s.set.occlusionMax);
	IHF_SECTION(scales);

	TableReader cloud(root["cloud"].as_table(), file, "cloud");
	cloud.get("normal_step", s.params.cloud.normalStep);
	cloud.get("max_jump_mm", s.params.cloud.maxJumpMm);
	cloud.get("max_jump_rel", s.params.cloud.maxJumpRel);
	cloud.get("pixel_stride", s.params.cloud.pixelStride);
	IHF_SECTION(cloud);

	TableReader ibs(root["ibs"].as_table(), file, "ibs");
	ibs.get("n", s.params.ibs.n);
	ibs.getEnum("solver", s.params.ibs.solver,
		    {{"cg", IbsSolver::kConjugateGradient}, {"mba", IbsSolver::kMultilevelBa}});
	ibs.get("offset_cells", s.params.ibs.offsetCells);
	ibs.get("offset_value", s.params.ibs.offsetValue);
	ibs.get("max_points", s.params.ibs.maxPoints);
	ibs.getEnum("warm_start", s.params.ibs.warmStart,
		    {{"zero", IbsWarmStart::kZero}, {"mba", IbsWarmStart::kMultilevelBa},
		     {"previous", IbsWarmStart::kPrevious}});
	ibs.get("cg_max_iterations", s.params.ibs.cgMaxIterations);
	ibs.get("cg_tolerance", s.params.ibs.cgTolerance);
	ibs.get("smoothness", s.params.ibs.smoothness);
	ibs.get("ridge", s.params.ibs.ridge);
	ibs.get("mba_levels", s.params.ibs.mbaLevels);
	IHF_SECTION(ibs);

	TableReader parts(root["parts"].as_table(), file, "parts");
	parts.getEnum("kind", s.params.parts.kind,
		      {{"variable", PartKind::kVariable}, {"fixed", PartKind::kFixed}});
	parts.get("stride", s.params.parts.stride);
	parts.get("fixed_fraction", s.params.parts.fixedFraction);
	parts.get("variable_side", s.params.parts.variableSide);
	parts.get("depth_margin_cells", s.params.parts.depthMarginCells);
	parts.get("max_control_points", s.params.parts.maxControlPoints);
	parts.getEnum("cap", s.params.parts.cap,
		      {{"uniform", PartCap::kUniform}, {"largest_weight", PartCap::kLargestWeight}});
	parts.get("min_data_points", s.params.parts.minDataPoints);
	IHF_SECTION(parts);

	TableReader hocp(root["hocp"].as_table(), file, "hocp");
	hocp.get("n_r", s.params.hocp.nR);
	hocp.get("n_theta", s.params.hocp.nTheta);
	hocp.get("n_phi", s.params.hocp.nPhi);
	hocp.get("r_min_fraction", s.params.hocp.rMinFraction);
	hocp.getEnum("weighting", s.params.hocp.weighting,
		     {{"count", HocpWeighting::kCount}, {"abs_weight", HocpWeighting::kAbsWeight},
		      {"sign_split", HocpWeighting::kSignSplit}});
	IHF_SECTION(hocp);
	if (std::string problem = hocpBinsProblem(s.params.hocp); !problem.empty())
		return makeError(Errc::kOutOfRange, file + ": hocp: " + problem);

	TableReader forest(root["forest"].as_table(), file, "forest");
	forest.get("trees", s.forest.trees);
	forest.get("max_depth", s.forest.maxDepth);
	forest.get("max_leaf_samples", s.forest.maxLeafSamples);
	forest.get("templates_per_node", s.forest.templatesPerNode);
	forest.get("sample_fraction", s.forest.sampleFraction);
	forest.getEnum("objective", s.forest.objective,
		       {{"alternate", SplitObjective::kAlternate}, {"offset", SplitObjective::kOffset},
			{"pose", SplitObjective::kPose}, {"sum", SplitObjective::kSum}});
	forest.get("depth_check_margin_mm", s.params.depthCheckMarginMm);
	forest.get("seed", s.forest.seed);
	forest.get("threads", s.forest.threads);
	forest.getEnum("encoding", s.encoding,
		       {{"uint8", TemplateEncoding::kUint8}, {"float32", TemplateEncoding::kFloat32}});
	IHF_SECTION(forest);

	s.set.seed = s.forest.seed;
	s.set.views.seed = s.forest.seed;
	s.set.threads = s.forest.threads;
	s.params.seed = s.forest.seed;
	return s;
}

Expected<BoxKind> parseBoxKind(const std::string &name, const std::string &what)
{
	if (name == "amodal")
		return BoxKind::kAmodal;
	if (name == "modal")
		return BoxKind::kModal;
	return makeError(Errc::kInvalidArgument, what + ": \"" + name + "\" is not a box kind (amodal or modal)");
}

const char *boxKindName(BoxKind kind)
{
	return kind == BoxKind::kModal ? "modal" : "amodal";
}

void useBoxKind(EstimateSettings &settings, BoxKind kind)
{
	const BoxKindWeights &w = kind == BoxKind::kModal ? settings.modal : settings.amodal;
	settings.boxKind = kind;
	settings.estimator.score.occludedWeight = w.occludedWeight;
	settings.estimator.score.boxWeight = w.boxWeight;
	settings.estimator.score.boxOccludedSide = w.boxOccludedSide;
}

void applyPapersMethod(EstimatorConfig &e)
{
	e.icp = false;
	e.views.inplane = 0;
	e.halfTurns.candidates = 0;
	iterationsAsRegistration(e);
}

Expected<EstimateSettings> loadEstimateConfig(const std::filesystem::path &path)
{
	EstimateSettings s;
	if (path.empty())
		return s;
	auto parsed = openConfig(path, {"refinement", "votes", "boxes", "score", "modal_boxes", "icp", "view_search", "half_turns", "confidence", "render_mesh", "budget", "limits"});
	if (!parsed)
		return parsed.error();
	const toml::table &root = *parsed;
	const std::string file = path.string();
	EstimatorConfig &e = s.estimator;

	TableReader ref(root["refinement"].as_table(), file, "refinement");
	ref.get("iterations", e.iterations);
	ref.get("psi1", e.psi1);
	ref.get("psi2", e.psi2);
	ref.get("part_stride", e.partStride);
	ref.get("target_parts", e.targetParts);
	ref.get("depth_windows", e.depthWindows);
	ref.get("hypothesis_cube", e.hypothesisCube);
	ref.get("depth_window_width", e.depthWindowWidth);
	ref.get("min_valid_pixels", e.minValidPixels);
	ref.get("iteration_ibs_max_points", e.iterationIbsMaxPoints);
	ref.get("iteration_ibs_cg_iterations", e.iterationIbsCgIterations);
	ref.get("iteration_max_shift_votes", e.iterationMaxShiftVotes);
	ref.get("iteration_target_parts", e.iterationTargetParts);
	ref.get("research_rounds", e.researchRounds);
	ref.get("research_polish", e.researchPolish);
	IHF_SECTION(ref);

	TableReader votes(root["votes"].as_table(), file, "votes");
	votes.get("max_hypotheses", e.maxHypotheses);
	votes.get("rotation_modes", e.rotationModes);
	votes.get("translation_bandwidth", e.translationBandwidth);
	votes.get("rotation_bandwidth_deg", e.rotationBandwidthDeg);
	votes.get("max_shift_votes", e.maxShiftVotes);
	IHF_SECTION(votes);

	TableReader boxes(root["boxes"].as_table(), file, "boxes");
	std::string kind = boxKindName(s.boxKind);
	boxes.get("kind", kind);
	IHF_SECTION(boxes);
	Expected<BoxKind> boxKind = parseBoxKind(kind, file + ": boxes.kind");
	if (!boxKind)
		return boxKind.error();

	TableReader score(root["score"].as_table(), file, "score");
	score.get("inlier_mm", e.score.inlierMm);
	score.get("occluded_weight", e.score.occludedWeight);
	score.get("outlier_weight", e.score.outlierWeight);
	score.get("box_weight", e.score.boxWeight);
	score.get("box_min_fill", e.score.boxMinFill);
	score.get("box_margin", e.score.boxMargin);
	score.get("residual_weight", e.score.residualWeight);
	score.get("skip_edge_outliers", e.score.skipEdgeOutliers);
	score.get("box_occluded_side", e.score.boxOccludedSide);
	score.get("box_occluded_band_px", e.score.boxOccludedBandPx);
	IHF_SECTION(score);

	TableReader modal(root["modal_boxes"].as_table(), file, "modal_boxes");
	modal.get("occluded_weight", s.modal.occludedWeight);
	modal.get("box_weight", s.modal.boxWeight);
	modal.get("box_occluded_side", s.modal.boxOccludedSide);
	IHF_SECTION(modal);

	TableReader icp(root["icp"].as_table(), file, "icp");
	icp.get("enabled", e.icp);
	icp.get("candidates", e.icpCandidates);
	icp.get("forest_bests", e.polishForestBests);
	icp.get("registration_candidates", e.polishRegistration);
	icp.get("iterations", e.icpConfig.iterations);
	icp.get("max_distance_mm", e.icpConfig.maxDistanceMm);
	icp.get("min_distance_mm", e.icpConfig.minDistanceMm);
	icp.get("render_once", e.icpConfig.renderOnce);
	IHF_SECTION(icp);

	TableReader views(root["view_search"].as_table(), file, "view_search");
	views.get("inplane", e.views.inplane);
	views.get("centres", e.views.centres);
	views.get("depth_centres", e.views.depthCentres);
	views.get("lateral_step_mm", e.views.lateralStepMm);
	views.get("rotation_step_deg", e.views.rotationStepDeg);
	views.get("anchor_share", e.views.anchorShare);
	views.get("depth_centre_width", e.views.depthCentreWidth);
	views.get("refine_top", e.views.refineTop);
	views.get("budget_rotation_step_deg", e.views.budgetRotationStepDeg);
	views.get("budget_refine_top", e.views.budgetRefineTop);
	views.get("budget_coarse_points", e.views.budgetCoarsePoints);
	views.get("budget_coarse_keep", e.views.budgetCoarseKeep);
	views.get("budget_depth_centres", e.views.budgetDepthCentres);
	views.get("budget_depth_centre_width", e.views.budgetDepthCentreWidth);
	views.get("budget_polish_rounds", e.views.budgetPolishRounds);
	views.get("depth_first", e.views.depthFirst);
	views.get("budget_depth_first", e.views.budgetDepthFirst);
	views.get("lean_search_below", e.views.leanSearchBelow);
	views.get("lean_rotation_step_deg", e.views.leanRotationStepDeg);
	views.get("lean_coarse_points", e.views.leanCoarsePoints);
	views.get("keep", e.views.keep);
	views.get("inlier_mm", e.views.inlierMm);
	views.get("max_shift_mm", e.views.maxShiftMm);
	views.get("distinct_deg", e.views.distinctDeg);
	views.get("box_centre", e.views.boxCentre);
	views.get("edge_insets", e.views.edgeInsets);
	views.get("edge_inset_share", e.views.edgeInsetShare);
	views.get("centre_shift_share", e.views.centreShiftShare);
	views.get("budget_centre_shift_share", e.views.budgetCentreShiftShare);
	views.get("coarse_at_centre", e.views.coarseAtCentre);
	views.get("coarse_points", e.views.coarsePoints);
	views.get("coarse_keep", e.views.coarseKeep);
	views.get("viewpoints", s.viewTemplates.viewpoints);
	views.get("budget_viewpoints", s.viewTemplates.budgetViewpoints);
	views.get("points", s.viewTemplates.pointsPerView);
	IHF_SECTION(views);

	TableReader turns(root["half_turns"].as_table(), file, "half_turns");
	turns.get("candidates", e.halfTurns.candidates);
	turns.get("axes", e.halfTurns.axes);
	turns.get("keep", e.halfTurns.keep);
	turns.get("align", e.halfTurns.align);
	turns.get("screen", e.halfTurns.screen);
	turns.get("box_axes", e.halfTurns.boxAxes);
	IHF_SECTION(turns);

	TableReader conf(root["confidence"].as_table(), file, "confidence");
	conf.get("distinct_share", e.confidence.distinctShare);
	conf.get("full_margin", e.confidence.fullMargin);
	IHF_SECTION(conf);

	TableReader render(root["render_mesh"].as_table(), file, "render_mesh");
	render.get("max_error_mm", s.renderMeshErrorMm);
	render.get("cull_back_faces", e.cullBackFaces);
	IHF_SECTION(render);

	TableReader budget(root["budget"].as_table(), file, "budget");
	budget.get("frame_ms", e.frameBudgetMs);
	budget.get("max_iterations", e.budgetIterations);
	budget.get("max_research_rounds", e.budgetResearchRounds);
	budget.get("max_depth_windows", e.budgetDepthWindows);
	budget.get("target_parts", e.budgetTargetParts);
	budget.get("ibs_max_points", e.budgetIbsMaxPoints);
	budget.get("ibs_cg_iterations", e.budgetIbsCgIterations);
	budget.get("tight_below_ms", e.budgetTightMs);
	budget.get("tight_target_parts", e.tightTargetParts);
	budget.get("tight_max_shift_votes", e.tightMaxShiftVotes);
	budget.get("tight_ibs_max_points", e.tightIbsMaxPoints);
	budget.get("tight_ibs_cg_iterations", e.tightIbsCgIterations);
	budget.get("tight_max_hypotheses", e.tightMaxHypotheses);
	budget.get("tight_rotation_modes", e.tightRotationModes);
	budget.get("tight_centre_shift_share", e.tightCentreShiftShare);
	budget.get("short_below_ms", e.budgetShortMs);
	budget.get("short_icp_iterations", e.shortIcpIterations);
	budget.get("short_icp_render_once", e.shortIcpRenderOnce);
	budget.get("short_occluded_weight", e.shortOccludedWeight);
	budget.get("scale_by_box", e.budgetScaleByBox);
	budget.get("max_window_pixels", e.budgetWindowPixels);
	budget.get("margin", e.budgetMargin);
	IHF_SECTION(budget);

	TableReader lim(root["limits"].as_table(), file, "limits");
	lim.get("max_window_pixels", s.limits.maxWindowPixels);
	lim.get("max_parts", s.limits.maxParts);
	lim.get("max_part_control_points", s.limits.maxPartControlPoints);
	lim.get("max_votes", s.limits.maxVotes);
	lim.get("max_active", s.limits.maxActive);
	lim.get("max_ibs_points", s.limits.maxIbsPoints);
	lim.get("max_ibs_n", s.limits.maxIbsN);
	lim.get("max_mesh_vertices", s.limits.maxMeshVertices);
	lim.get("max_histogram_dims", s.limits.maxHistogramDims);
	lim.get("max_modes", s.limits.maxModes);
	lim.get("max_mode_seeds", s.limits.maxModeSeeds);
	lim.get("max_candidates", s.limits.maxCandidates);
	lim.get("max_rivals", s.limits.maxRivals);
	lim.get("threads", s.limits.threads);
	IHF_SECTION(lim);

	const auto inRange = [&](bool ok, const char *key) { return rangeCheck(ok, file, key); };
	for (Status st : {inRange(e.iterations >= 0, "refinement.iterations"),
			  inRange(e.psi1 > 0 && e.psi2 >= e.psi1, "refinement.psi1/psi2"),
			  inRange(e.depthWindows >= 0 && e.depthWindows <= 8, "refinement.depth_windows"),
			  inRange(e.iterationIbsMaxPoints >= 0, "refinement.iteration_ibs_max_points"),
			  inRange(e.iterationIbsCgIterations >= 0, "refinement.iteration_ibs_cg_iterations"),
			  inRange(e.iterationMaxShiftVotes >= 0, "refinement.iteration_max_shift_votes"),
			  inRange(e.iterationTargetParts >= 0, "refinement.iteration_target_parts"),
			  inRange(e.researchRounds >= 0, "refinement.research_rounds"),
			  inRange(e.researchPolish >= 0 && e.researchPolish <= kMaxViewKeep, "refinement.research_polish"),
			  inRange(e.maxHypotheses >= 1, "votes.max_hypotheses"),
			  inRange(e.rotationModes >= 1 && e.rotationModes <= 16, "votes.rotation_modes"),
			  inRange(e.maxShiftVotes >= 0, "votes.max_shift_votes"),
			  inRange(e.score.outlierWeight >= 0, "score.outlier_weight"),
			  inRange(e.score.occludedWeight >= 0, "score.occluded_weight"),
			  inRange(e.score.boxWeight >= 0, "score.box_weight"),
			  inRange(s.modal.boxWeight >= 0, "modal_boxes.box_weight"),
			  inRange(e.score.boxOccludedSide >= 0 && e.score.boxOccludedSide <= 1, "score.box_occluded_side"),
			  inRange(e.score.boxOccludedBandPx >= 1, "score.box_occluded_band_px"),
			  inRange(s.modal.occludedWeight >= 0, "modal_boxes.occluded_weight"),
			  inRange(s.modal.boxOccludedSide >= 0 && s.modal.boxOccludedSide <= 1,
				  "modal_boxes.box_occluded_side"),
			  inRange(e.score.residualWeight >= 0 && e.score.residualWeight <= 1, "score.residual_weight"),
			  inRange(e.icpCandidates >= 0, "icp.candidates"),
			  inRange(e.views.inplane >= 0 && e.views.inplane <= kMaxInplane, "view_search.inplane"),
			  inRange(e.views.centres >= 1 && e.views.centres <= 4, "view_search.centres"),
			  inRange(e.views.depthCentres >= 0 && e.views.depthCentres <= 4, "view_search.depth_centres"),
			  inRange(e.views.lateralStepMm >= 0, "view_search.lateral_step_mm"),
			  inRange(e.views.rotationStepDeg >= 0 && e.views.rotationStepDeg <= 45,
				  "view_search.rotation_step_deg"),
			  inRange(e.views.anchorShare > 0 && e.views.anchorShare <= 1, "view_search.anchor_share"),
			  inRange(e.views.depthCentreWidth >= 0 && e.views.depthCentreWidth <= 10,
				  "view_search.depth_centre_width"),
			  inRange(e.views.budgetDepthCentreWidth >= 0 && e.views.budgetDepthCentreWidth <= 10,
				  "view_search.budget_depth_centre_width"),
			  inRange(e.views.budgetPolishRounds >= 0 && e.views.budgetPolishRounds <= 16,
				  "view_search.budget_polish_rounds"),
			  inRange(e.views.refineTop >= 1 && e.views.refineTop <= kMaxRefineTop, "view_search.refine_top"),
			  inRange(e.views.budgetRotationStepDeg >= 0 && e.views.budgetRotationStepDeg <= 45,
				  "view_search.budget_rotation_step_deg"),
			  inRange(e.views.budgetRefineTop >= 1 && e.views.budgetRefineTop <= kMaxRefineTop,
				  "view_search.budget_refine_top"),
			  inRange(e.views.keep >= 1 && e.views.keep <= kMaxViewKeep, "view_search.keep"),
			  inRange(e.views.edgeInsets >= 0 && e.views.edgeInsets <= 8, "view_search.edge_insets"),
			  inRange(e.views.edgeInsetShare >= 0 && e.views.edgeInsetShare <= 0.5f, "view_search.edge_inset_share"),
			  inRange(e.views.centreShiftShare >= 0 && e.views.centreShiftShare <= 0.5f,
				  "view_search.centre_shift_share"),
			  inRange(e.views.budgetCentreShiftShare >= 0 && e.views.budgetCentreShiftShare <= 0.5f,
				  "view_search.budget_centre_shift_share"),
			  inRange(e.views.inlierMm > 0, "view_search.inlier_mm"),
			  inRange(e.views.maxShiftMm >= 0, "view_search.max_shift_mm"),
			  inRange(e.views.distinctDeg >= 0, "view_search.distinct_deg"),
			  inRange(e.views.coarsePoints >= 0 && e.views.coarsePoints <= kMaxViewPoints, "view_search.coarse_points"),
			  inRange(e.views.coarseKeep >= 1 && e.views.coarseKeep <= kMaxCoarseKeep, "view_search.coarse_keep"),
			  inRange(e.views.budgetCoarsePoints >= 0 && e.views.budgetCoarsePoints <= kMaxViewPoints,
				  "view_search.budget_coarse_points"),
			  inRange(e.views.budgetCoarseKeep >= 1 && e.views.budgetCoarseKeep <= kMaxCoarseKeep,
				  "view_search.budget_coarse_keep"),
			  inRange(e.views.budgetDepthCentres >= 0 && e.views.budgetDepthCentres <= 4,
				  "view_search.budget_depth_centres"),
			  inRange(e.views.leanSearchBelow >= 0 && e.views.leanSearchBelow <= 1000,
				  "view_search.lean_search_below"),
			  inRange(e.views.leanRotationStepDeg >= 0 && e.views.leanRotationStepDeg <= 45,
				  "view_search.lean_rotation_step_deg"),
			  inRange(e.views.leanCoarsePoints >= 0 && e.views.leanCoarsePoints <= kMaxViewPoints,
				  "view_search.lean_coarse_points"),
			  inRange(s.viewTemplates.viewpoints >= 1 && s.viewTemplates.viewpoints <= 100000, "view_search.viewpoints"),
			  inRange(s.viewTemplates.budgetViewpoints >= 1 && s.viewTemplates.budgetViewpoints <= 100000,
				  "view_search.budget_viewpoints"),
			  inRange(s.viewTemplates.pointsPerView >= 8 && s.viewTemplates.pointsPerView <= kMaxViewPoints, "view_search.points"),
			  inRange(e.halfTurns.candidates >= 0 && e.halfTurns.candidates <= 4, "half_turns.candidates"),
			  inRange(e.halfTurns.axes >= 0 && e.halfTurns.axes <= 1024, "half_turns.axes"),
			  inRange(e.halfTurns.screen >= 0 && e.halfTurns.screen <= kMaxHalfTurnScreen, "half_turns.screen"),
			  inRange(e.halfTurns.keep >= 1 && e.halfTurns.keep <= kMaxHalfTurnKeep, "half_turns.keep"),
			  inRange(e.confidence.distinctShare > 0 && e.confidence.distinctShare <= 1,
				  "confidence.distinct_share"),
			  inRange(e.confidence.fullMargin >= 0 && e.confidence.fullMargin <= 1, "confidence.full_margin"),
			  inRange(s.limits.maxRivals >= 0, "limits.max_rivals"),
			  inRange(s.renderMeshErrorMm >= 0 && s.renderMeshErrorMm <= 20, "render_mesh.max_error_mm"),
			  inRange(e.frameBudgetMs >= 0, "budget.frame_ms"),
			  inRange(e.budgetIterations >= -1, "budget.max_iterations"),
			  inRange(e.budgetResearchRounds >= -1, "budget.max_research_rounds"),
			  inRange(e.budgetDepthWindows >= -1, "budget.max_depth_windows"),
			  inRange(e.budgetTargetParts >= 0, "budget.target_parts"),
			  inRange(e.budgetIbsMaxPoints >= 0, "budget.ibs_max_points"),
			  inRange(e.budgetIbsCgIterations >= 0, "budget.ibs_cg_iterations"),
			  inRange(e.budgetTightMs >= 0, "budget.tight_below_ms"),
			  inRange(e.tightTargetParts >= 0, "budget.tight_target_parts"),
			  inRange(e.tightMaxShiftVotes >= 0, "budget.tight_max_shift_votes"),
			  inRange(e.tightIbsMaxPoints >= 0, "budget.tight_ibs_max_points"),
			  inRange(e.tightIbsCgIterations >= 0, "budget.tight_ibs_cg_iterations"),
			  inRange(e.tightMaxHypotheses >= 0, "budget.tight_max_hypotheses"),
			  inRange(e.tightRotationModes >= 0, "budget.tight_rotation_modes"),
			  inRange(e.tightCentreShiftShare >= 0 && e.tightCentreShiftShare <= 0.5f,
				  "budget.tight_centre_shift_share"),
			  inRange(e.budgetShortMs >= 0, "budget.short_below_ms"),
			  inRange(e.shortIcpIterations >= 0, "budget.short_icp_iterations"),
			  inRange(std::isfinite(e.shortOccludedWeight), "budget.short_occluded_weight"),
			  inRange(e.budgetWindowPixels >= 0, "budget.max_window_pixels"),
			  inRange(e.budgetMargin >= 0 && e.budgetMargin <= 10, "budget.margin"),
			  inRange(s.limits.threads >= 0 && s.limits.threads <= WorkerPool::kMaxThreads, "limits.threads")})
		if (!st)
			return st.error();
	s.amodal = {e.score.occludedWeight, e.score.boxWeight, e.score.boxOccludedSide};
	useBoxKind(s, *boxKind);
	return s;
}

namespace {

// "scheme:PATH" with a relative PATH becomes relative to base.
std::string resolveUri(const std::string &uri, const std::filesystem::path &base,
		       std::initializer_list<const char *> fileSchemes)
{
	const size_t colon = uri.find(':');
	if (colon == std::string::npos)
		return uri;
	const std::string scheme = uri.substr(0, colon);
	const std::filesystem::path rest = uri.substr(colon + 1);
	for (const char *s : fileSchemes)
		if (scheme == s && !rest.empty() && rest.is_relative())
			return scheme + ":" + (base / rest).lexically_normal().string();
	return uri;
}

} // namespace

Expected<RunSettings> loadRunConfig(const std::filesystem::path &path)
{
	RunSettings s;
	if (path.empty())
		return s;
	auto parsed = openConfig(path, {"source", "boxes", "output", "objects", "estimate", "tracking", "run"});
	if (!parsed)
		return parsed.error();
	const toml::table &root = *parsed;
	const std::string file = path.string();
	const std::filesystem::path base = path.parent_path();

	TableReader src(root["source"].as_table(), file, "source");
	src.get("uri", s.sourceUri);
	src.getEnum("pacing", s.realTime, {{"step", false}, {"real_time", true}});
	src.get("speed", s.speed);
	src.get("timeout_ms", s.timeoutMs);
	src.get("max_retries", s.maxRetries);
	src.get("retry_backoff_ms", s.retryBackoffMs);
	src.get("retry_backoff_max_ms", s.retryBackoffMaxMs);
	src.get("usb_watch", s.usbWatch);
	IHF_SECTION(src);

	TableReader boxes(root["boxes"].as_table(), file, "boxes");
	boxes.get("input", s.boxes);
	boxes.get("timeout_ms", s.boxesTimeoutMs);
	std::string kind;
	boxes.get("kind", kind);
	IHF_SECTION(boxes);
	if (!kind.empty()) {
		Expected<BoxKind> k = parseBoxKind(kind, file + ": boxes.kind");
		if (!k)
			return k.error();
		s.boxKind = *k;
	}

	TableReader out(root["output"].as_table(), file, "output");
	out.get("poses", s.poses);
	IHF_SECTION(out);

	if (const toml::table *objects = root["objects"].as_table()) {
		for (const auto &[k, v] : *objects) {
			const std::string key(k.str());
			int id = -1;
			try {
				size_t used = 0;
				id = std::stoi(key, &used);
				if (used != key.size())
					id = -1;
			} catch (...) {
			}
			if (id < 0)
				return makeError(Errc::kParse, file + ": objects." + key +
								       ": keys are object ids (\"20\" = \"bunny.ihf\")");
			auto forest = v.value_exact<std::string>();
			if (!forest)
				return makeError(Errc::kParse, file + ": objects." + key + ": expected a forest file path");
			std::filesystem::path f = *forest;
			s.forests[id] = f.is_relative() ? (base / f).lexically_normal() : f;
		}
	}

	TableReader est(root["estimate"].as_table(), file, "estimate");
	std::string estimateConfig;
	est.get("config", estimateConfig);
	est.get("iterations", s.iterations);
	est.get("budget_ms", s.budgetMs);
	IHF_SECTION(est);
	if (!estimateConfig.empty()) {
		s.estimateConfig = estimateConfig;
		if (s.estimateConfig.is_relative())
			s.estimateConfig = (base / s.estimateConfig).lexically_normal();
	}

	TableReader tracking(root["tracking"].as_table(), file, "tracking");
	TrackerConfig &tc = s.tracking;
	tracking.get("enabled", tc.enabled);
	tracking.get("match_iou", tc.matchIou);
	tracking.get("max_missed_frames", tc.maxMissedFrames);
	tracking.get("max_defer_frames", tc.maxDeferFrames);
	tracking.get("detect_min_ms", tc.detectMinMs);
	tracking.get("refresh", tc.refresh);
	tracking.get("min_score", tc.minScore);
	tracking.get("keep_share", tc.keepShare);
	IHF_SECTION(tracking);

	TableReader run(root["run"].as_table(), file, "run");
	run.get("frame_budget_ms", s.frameBudgetMs);
	run.get("stats_interval_s", s.statsIntervalS);
	run.get("max_frames", s.maxFrames);
	IHF_SECTION(run);

	const auto positive = [&](bool ok, const char *key) { return rangeCheck(ok, file, key); };
	for (Status st : {positive(s.speed > 0, "source.speed"), positive(s.timeoutMs > 0, "source.timeout_ms"),
			  positive(s.maxRetries >= 0, "source.max_retries"),
			  positive(s.retryBackoffMs >= 0, "source.retry_backoff_ms"),
			  positive(s.retryBackoffMaxMs >= s.retryBackoffMs, "source.retry_backoff_max_ms"),
			  positive(s.boxesTimeoutMs >= 0, "boxes.timeout_ms"),
			  positive(s.frameBudgetMs >= 0, "run.frame_budget_ms"),
			  positive(tc.matchIou > 0 && tc.matchIou <= 1, "tracking.match_iou"),
			  positive(tc.maxMissedFrames >= 1, "tracking.max_missed_frames"),
			  positive(tc.maxDeferFrames >= 1, "tracking.max_defer_frames"),
			  positive(tc.detectMinMs >= 0, "tracking.detect_min_ms"),
			  positive(tc.minScore >= 0 && tc.minScore <= 1, "tracking.min_score"),
			  positive(tc.keepShare >= 0 && tc.keepShare <= 1, "tracking.keep_share"),
			  positive(s.statsIntervalS >= 0, "run.stats_interval_s"),
			  positive(s.maxFrames >= 0, "run.max_frames")})
		if (!st)
			return st.error();

	s.sourceUri = resolveUri(s.sourceUri, base, {"recording"});
	s.boxes = resolveUri(s.boxes, base, {"file", "unix"});
	s.poses = resolveUri(s.poses, base, {"file"});
	return s;
}

Status prepareModel(ObjectModel &model, const EstimateSettings &settings)
{
	if (settings.estimator.views.inplane > 0 && model.viewTemplates().empty()) {
		// Inside a frame budget the search runs on fewer viewpoints: at
		// the offline count it does not fit a 33 ms frame at all.
		ViewTemplateConfig vt = settings.viewTemplates;
		if (settings.estimator.frameBudgetMs > 0)
			vt.viewpoints = vt.budgetViewpoints;
		auto points = buildViewTemplatePoints(model.mesh(), model.params().diameter, vt);
		if (!points)
			return points.error();
		model.attachViewTemplates(vt.viewpoints, vt.pointsPerView, std::move(*points));
	}
	if (settings.renderMeshErrorMm > 0) {
		auto simple = simplifyMesh(model.mesh(), settings.renderMeshErrorMm);
		if (!simple)
			return simple.error();
		model.attachRenderMesh(std::move(simple->mesh));
	}
	return {};
}

void growLimitsFor(EstimatorLimits &limits, const ObjectModel &model)
{
	limits.maxMeshVertices = std::max(limits.maxMeshVertices, model.renderMesh().vertices.size());
	limits.maxIbsN = std::max(limits.maxIbsN, model.params().ibs.n);
	limits.maxIbsPoints = std::max(limits.maxIbsPoints, model.params().ibs.maxPoints);
	limits.maxHistogramDims = std::max(limits.maxHistogramDims, model.forest().dims);
}

} // namespace ihf::app
