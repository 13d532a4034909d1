// SPDX-License-Identifier: MIT
#include "core/eval/eval_report_json.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/dataset/atomic_file.h"
#include "core/eval/visible_surface.h"

namespace ihf {

namespace {

using nlohmann::json;

json timeJson(double seconds)
{
	return seconds < 0 ? json(nullptr) : json(seconds);
}

json curveJson(const std::vector<PrPoint> &curve)
{
	json points = json::array();
	for (const PrPoint &p : curve)
		points.push_back({{"threshold", p.threshold},
				  {"precision", p.precision},
				  {"recall", p.recall},
				  {"f1", p.f1}});
	return points;
}

} // namespace

int curveZIndex(const EvalReport &report, double z)
{
	for (size_t i = 0; i < report.zValues.size(); ++i)
		if (std::abs(report.zValues[i] - z) < 1e-9)
			return static_cast<int>(i);
	return -1;
}

std::string evalReportJson(const EvalReport &report)
{
	const int zi = curveZIndex(report);

	json objects = json::array();
	for (const ObjectEvalResult &r : report.objects) {
		json o = {
			{"obj_id", r.objId},
			{"metric", poseMetricName(r.metric)},
			{"diameter", r.diameter},
			{"num_gt", r.numGt},
			{"num_estimates", r.numEstimates},
			{"num_matched", r.numMatched},
			{"f1", r.f1},
			{"mean_f1", r.meanF1},
			{"recall_0.1d", r.recall},
			{"median_time", timeJson(r.medianTime)},
		};
		if (r.arVsd >= 0)
			o["ar_vsd"] = r.arVsd;
		if (zi >= 0)
			o["pr_curve_z0.10"] = curveJson(r.curves[static_cast<size_t>(zi)]);
		objects.push_back(std::move(o));
	}

	json estimates = json::array();
	for (const EstimateOutcome &e : report.estimates) {
		json row = {{"scene_id", e.sceneId},
			    {"im_id", e.imId},
			    {"obj_id", e.objId},
			    {"score", e.score},
			    {"matched", e.matched},
			    {"error_mm", e.matched ? json(e.error) : json(nullptr)}};
		if (e.vsdShare >= 0)
			row["vsd_share"] = e.vsdShare;
		estimates.push_back(std::move(row));
	}

	json doc = {
		{"z_values", report.zValues},
		{"estimates", std::move(estimates)},
		{"recall_z", kRecallZ},
		{"objects", std::move(objects)},
		{"mean",
		 {
			 {"f1", report.meanF1PerZ},
			 {"mean_f1", report.meanF1},
			 {"recall_0.1d", report.meanRecall},
			 {"median_time", timeJson(report.medianTime)},
			 {"num_gt", report.numGt},
			 {"num_estimates", report.numEstimates},
			 {"num_ignored", report.numIgnored},
		 }},
	};
	if (report.meanArVsd >= 0) {
		doc["mean"]["ar_vsd"] = report.meanArVsd;
		doc["vsd"] = {{"delta_mm", kVsdDeltaMm}, {"tau_shares", vsdTauShares()}, {"thetas", vsdThetas()}};
	}
	return doc.dump(2) + "\n";
}

Status writeEvalReportJson(const std::filesystem::path &file, const EvalReport &report)
{
	return writeFileAtomic(file, evalReportJson(report));
}

} // namespace ihf
