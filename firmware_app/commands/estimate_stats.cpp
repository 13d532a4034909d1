// SPDX-License-Identifier: MIT
#include "firmware_app/commands/estimate_stats.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

namespace ihf::app {

double percentile(std::vector<double> values, double p)
{
	if (values.empty())
		return 0;
	std::sort(values.begin(), values.end());
	const double r = std::floor(p * static_cast<double>(values.size() - 1) + 0.5);
	return values[static_cast<size_t>(std::clamp(r, 0.0, static_cast<double>(values.size() - 1)))];
}

namespace {

double ms(int64_t ns)
{
	return static_cast<double>(ns) * 1e-6;
}

double mib(size_t bytes)
{
	return static_cast<double>(bytes) / (1024.0 * 1024.0);
}

} // namespace

void printEstimateStats(std::FILE *out, const EstimateRunSummary &sum)
{
	const EstimatorStats &s = sum.stats;
	int64_t total = 0;
	for (const auto &c : s.stages)
		total += c.totalNs;
	std::fprintf(out, "ihf estimate: time per stage (all boxes):\n");
	std::fprintf(out, "  %-13s %10s %8s %9s %9s %6s\n", "stage", "total ms", "calls", "mean ms", "max ms",
		     "share");
	for (int i = 0; i < kStageCount; ++i) {
		const StageCounter &c = s.stages[i];
		std::fprintf(out, "  %-13s %10.1f %8llu %9.3f %9.3f %5.1f%%\n", stageName(static_cast<Stage>(i)),
			     ms(c.totalNs), static_cast<unsigned long long>(c.calls),
			     c.calls ? ms(c.totalNs) / static_cast<double>(c.calls) : 0.0, ms(c.maxNs),
			     total > 0 ? 100.0 * static_cast<double>(c.totalNs) / static_cast<double>(total) : 0.0);
	}
	char profiles[112] = "";
	if (sum.frameBudgetMs > 0) {
		std::snprintf(profiles, sizeof(profiles), " (%llu tight, %llu short, %llu lean search)",
			      static_cast<unsigned long long>(s.tightBoxes), static_cast<unsigned long long>(s.shortBoxes),
			      static_cast<unsigned long long>(s.leanSearchBoxes));
		std::fprintf(out, "ihf estimate: budget %g ms per frame: ", sum.frameBudgetMs);
	} else {
		std::fprintf(out, "ihf estimate: no frame budget: ");
	}
	std::fprintf(out,
		     "%llu frames, %llu boxes%s, %llu refinement iterations, %llu re-searches (%llu better, %llu "
		     "left out), %llu boxes cut short, "
		     "%llu ICP skipped, %llu frame overruns, %llu box overruns (%llu already in the initial "
		     "registration), worst frame %.1f ms\n",
		     static_cast<unsigned long long>(s.frames), static_cast<unsigned long long>(s.boxes),
		     profiles, static_cast<unsigned long long>(s.iterations), static_cast<unsigned long long>(s.researches),
		     static_cast<unsigned long long>(s.researchWins), static_cast<unsigned long long>(s.researchesSkipped),
		     static_cast<unsigned long long>(s.budgetStops),
		     static_cast<unsigned long long>(s.icpSkipped), static_cast<unsigned long long>(s.frameOverruns),
		     static_cast<unsigned long long>(s.boxOverruns),
		     static_cast<unsigned long long>(s.registrationOverruns), ms(s.worstFrameNs));
	std::fprintf(out, "ihf estimate: boxes taken as %s: occluded weight %.2f, box power %.2f, occluded side %.2f\n",
		     sum.boxKind, static_cast<double>(sum.score.occludedWeight), static_cast<double>(sum.score.boxWeight),
		     static_cast<double>(sum.score.boxOccludedSide));
	std::fprintf(out,
		     "ihf estimate: arena used %zu bytes (%.1f MiB) of %zu (%.1f MiB); persistent %zu (%.1f MiB)\n",
		     s.arenaHighWater, mib(s.arenaHighWater), s.arenaCapacity, mib(s.arenaCapacity),
		     s.arenaPersistent, mib(s.arenaPersistent));
	const EstimatorLimits &l = sum.limits;
	const EstimatorPeaks &p = s.peaks;
	std::fprintf(out,
		     "ihf estimate: largest use of the limits: window %d/%d px, cloud %d points, active control "
		     "points %d/%d, parts %d/%d, part control points %d/%lld, votes %d/%d\n",
		     p.windowPixels, l.maxWindowPixels, p.cloudPoints, p.activeControlPoints, l.maxActive, p.parts,
		     l.maxParts, p.poolControlPoints,
		     static_cast<long long>(l.maxParts) * l.maxPartControlPoints, p.votes, l.maxVotes);
}

std::string estimateStatsJson(const EstimateRunSummary &sum)
{
	const EstimatorStats &s = sum.stats;
	nlohmann::ordered_json j;
	nlohmann::ordered_json stages = nlohmann::ordered_json::object();
	for (int i = 0; i < kStageCount; ++i) {
		const StageCounter &c = s.stages[i];
		stages[stageName(static_cast<Stage>(i))] = {
			{"calls", c.calls}, {"total_ms", ms(c.totalNs)}, {"max_ms", ms(c.maxNs)}};
	}
	j["stages"] = stages;
	j["box_ms"] = {{"count", sum.boxSeconds.size()},
		       {"p50", 1e3 * percentile(sum.boxSeconds, 0.5)},
		       {"p90", 1e3 * percentile(sum.boxSeconds, 0.9)},
		       {"p99", 1e3 * percentile(sum.boxSeconds, 0.99)},
		       {"max", 1e3 * percentile(sum.boxSeconds, 1.0)}};
	j["budget"] = {{"frame_ms", sum.frameBudgetMs},
		       {"frames", s.frames},
		       {"boxes", s.boxes},
		       {"tight_boxes", s.tightBoxes},
		       {"short_boxes", s.shortBoxes},
		       {"lean_search_boxes", s.leanSearchBoxes},
		       {"refinement_iterations", s.iterations},
		       {"researches", s.researches},
		       {"research_wins", s.researchWins},
		       {"researches_skipped", s.researchesSkipped},
		       {"budget_stops", s.budgetStops},
		       {"icp_skipped", s.icpSkipped},
		       {"frame_overruns", s.frameOverruns},
		       {"box_overruns", s.boxOverruns},
		       {"registration_overruns", s.registrationOverruns},
		       {"worst_frame_ms", ms(s.worstFrameNs)}};
	j["score"] = {{"box_kind", sum.boxKind},
		      {"occluded_weight", sum.score.occludedWeight},
		      {"box_weight", sum.score.boxWeight},
		      {"box_occluded_side", sum.score.boxOccludedSide}};
	nlohmann::ordered_json ambiguous = nlohmann::ordered_json::array();
	for (const AmbiguousPose &a : sum.ambiguous)
		ambiguous.push_back({{"scene_id", a.sceneId},
				     {"im_id", a.imId},
				     {"obj_id", a.objId},
				     {"axis", {a.axis.x(), a.axis.y(), a.axis.z()}}});
	j["ambiguous_poses"] = ambiguous;
	j["arena"] = {{"capacity_bytes", s.arenaCapacity},
		      {"persistent_bytes", s.arenaPersistent},
		      {"used_bytes", s.arenaHighWater}};
	const EstimatorLimits &l = sum.limits;
	const EstimatorPeaks &p = s.peaks;
	j["limits_used"] = {
		{"window_pixels", {p.windowPixels, l.maxWindowPixels}},
		{"cloud_points", {p.cloudPoints, l.maxWindowPixels}},
		{"active_control_points", {p.activeControlPoints, l.maxActive}},
		{"parts", {p.parts, l.maxParts}},
		{"part_control_points",
		 {p.poolControlPoints, static_cast<long long>(l.maxParts) * l.maxPartControlPoints}},
		{"votes", {p.votes, l.maxVotes}}};
	return j.dump(2) + "\n";
}

} // namespace ihf::app
