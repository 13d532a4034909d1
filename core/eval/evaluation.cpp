// SPDX-License-Identifier: MIT
#include "core/eval/evaluation.h"

#include <algorithm>
#include <tuple>

#include "core/eval/matching.h"
#include "core/runtime/worker_pool.h"

namespace ihf {

std::vector<double> defaultZValues()
{
	std::vector<double> z;
	for (int i = 5; i <= 15; ++i)
		z.push_back(i / 100.0);
	return z;
}

double medianKnown(std::vector<double> values)
{
	std::erase_if(values, [](double v) { return !(v >= 0); });
	if (values.empty())
		return -1;
	std::sort(values.begin(), values.end());
	const size_t n = values.size();
	return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

namespace {

using GroupKey = std::tuple<int, int, int>; // object, scene, image
using ImageKey = std::pair<int, int>;       // scene, image

struct Group {
	int objId = 0;
	std::vector<size_t> gts;       // indices into gts
	std::vector<size_t> estimates; // indices into estimates
	MatchResult match;
};

// Pose errors dominate (ADI runs a KD-tree query per vertex), so every
// (estimate, instance) pair is shared out over the cores; matching is cheap.
void matchGroups(std::vector<Group> &groups, const std::map<int, EvalObject> &objects,
		 const std::vector<EvalGt> &gts, const std::vector<ResultRow> &estimates)
{
	struct Pair {
		size_t group, e, g;
	};
	std::vector<Pair> pairs;
	std::vector<Eigen::MatrixXd> errors(groups.size());
	for (size_t i = 0; i < groups.size(); ++i) {
		const Group &g = groups[i];
		errors[i].resize(static_cast<Eigen::Index>(g.estimates.size()),
				 static_cast<Eigen::Index>(g.gts.size()));
		for (size_t e = 0; e < g.estimates.size(); ++e)
			for (size_t k = 0; k < g.gts.size(); ++k)
				pairs.push_back({i, e, k});
	}

	WorkerPool pool(0);
	pool.run(static_cast<int>(pairs.size()), [&](int i, int) {
		const Pair &p = pairs[static_cast<size_t>(i)];
		const Group &g = groups[p.group];
		const ObjectPoseError &error = *objects.at(g.objId).error;
		errors[p.group](static_cast<Eigen::Index>(p.e), static_cast<Eigen::Index>(p.g)) =
			error(estimates[g.estimates[p.e]].pose, gts[g.gts[p.g]].pose);
	});

	for (size_t i = 0; i < groups.size(); ++i) {
		std::vector<double> scores;
		for (size_t e : groups[i].estimates)
			scores.push_back(estimates[e].score);
		groups[i].match = matchGreedy(scores, errors[i]);
	}
}

// Per estimate of the group, the share of the (tau, theta) pairs at which it
// is correct by the visible surface: matched again for each tau on e_VSD.
std::vector<double> visibleSurfaceShares(const Group &g, const std::vector<ResultRow> &estimates,
					 const VsdErrors &vsd)
{
	std::vector<double> scores;
	for (size_t e : g.estimates)
		scores.push_back(estimates[e].score);
	std::vector<int> correct(g.estimates.size(), 0); // (tau, theta) pairs
	for (size_t tau = 0; tau < vsd.tauShares.size(); ++tau) {
		Eigen::MatrixXd errors(static_cast<Eigen::Index>(g.estimates.size()),
				       static_cast<Eigen::Index>(g.gts.size()));
		for (size_t e = 0; e < g.estimates.size(); ++e)
			for (size_t k = 0; k < g.gts.size(); ++k)
				errors(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(k)) =
					vsd.errors.at({g.estimates[e], g.gts[k]})[tau];
		const MatchResult match = matchGreedy(scores, errors);
		for (size_t e = 0; e < g.estimates.size(); ++e) {
			if (match.gtOfEstimate[e] < 0)
				continue;
			for (double theta : vsd.thetas)
				correct[e] += match.estimateError[e] < theta;
		}
	}
	const double pairs = static_cast<double>(vsd.tauShares.size() * vsd.thetas.size());
	std::vector<double> shares;
	for (int c : correct)
		shares.push_back(c / pairs);
	return shares;
}

// Largest known time per image (rows of one image should agree).
void addImageTime(std::map<ImageKey, double> &times, const ResultRow &row)
{
	auto [it, inserted] = times.try_emplace({row.sceneId, row.imId}, row.time);
	if (!inserted)
		it->second = std::max(it->second, row.time);
}

std::vector<double> timeValues(const std::map<ImageKey, double> &times)
{
	std::vector<double> values;
	for (const auto &[key, t] : times)
		values.push_back(t);
	return values;
}

} // namespace

EvalReport evaluatePoses(const std::map<int, EvalObject> &objects,
			 const std::vector<EvalGt> &gts,
			 const std::vector<ResultRow> &estimates,
			 const std::vector<double> &zValues,
			 const VsdErrors *vsd)
{
	std::map<GroupKey, Group> byKey;
	for (size_t i = 0; i < gts.size(); ++i) {
		const EvalGt &gt = gts[i];
		if (!objects.count(gt.objId))
			continue;
		Group &g = byKey[{gt.objId, gt.sceneId, gt.imId}];
		g.objId = gt.objId;
		g.gts.push_back(i);
	}
	for (size_t i = 0; i < estimates.size(); ++i) {
		const ResultRow &row = estimates[i];
		if (!objects.count(row.objId))
			continue;
		Group &g = byKey[{row.objId, row.sceneId, row.imId}];
		g.objId = row.objId;
		g.estimates.push_back(i);
	}

	std::vector<Group> groups;
	groups.reserve(byKey.size());
	for (auto &[key, g] : byKey)
		groups.push_back(std::move(g));
	matchGroups(groups, objects, gts, estimates);

	// Per object: the (score, error) of every estimate and the GT count.
	struct Acc {
		std::vector<ScoredOutcome> outcomes;
		size_t numGt = 0;
		size_t numMatched = 0;
		double vsdCorrect = 0; // sum of the estimates' shares
		std::map<ImageKey, double> times;
	};
	std::map<int, Acc> acc;
	std::map<ImageKey, double> allTimes;
	std::vector<EstimateOutcome> perEstimate;
	for (const Group &g : groups) {
		Acc &a = acc[g.objId];
		a.numGt += g.gts.size();
		const std::vector<double> shares =
			vsd ? visibleSurfaceShares(g, estimates, *vsd) : std::vector<double>(g.estimates.size(), -1.0);
		for (size_t e = 0; e < g.estimates.size(); ++e) {
			const ResultRow &row = estimates[g.estimates[e]];
			a.outcomes.push_back({row.score, g.match.estimateError[e]});
			const bool matched = g.match.gtOfEstimate[e] >= 0;
			if (matched)
				++a.numMatched;
			perEstimate.push_back({row.sceneId, row.imId, row.objId, row.score, matched,
					       matched ? g.match.estimateError[e] : 0.0, shares[e]});
			if (vsd)
				a.vsdCorrect += shares[e];
			addImageTime(a.times, row);
			addImageTime(allTimes, row);
		}
	}

	EvalReport report;
	report.estimates = std::move(perEstimate);
	report.zValues = zValues;
	report.meanF1PerZ.assign(zValues.size(), 0.0);
	for (const auto &[objId, object] : objects) {
		const Acc &a = acc[objId];
		ObjectEvalResult r;
		r.objId = objId;
		r.metric = object.error->metric();
		r.diameter = object.diameter;
		r.numGt = a.numGt;
		r.numEstimates = a.outcomes.size();
		r.numMatched = a.numMatched;
		for (double z : zValues) {
			r.curves.push_back(prCurve(a.outcomes, a.numGt, z * object.diameter));
			r.f1.push_back(bestF1(r.curves.back()));
		}
		r.meanF1 = 0;
		for (double f : r.f1)
			r.meanF1 += f;
		if (!r.f1.empty())
			r.meanF1 /= static_cast<double>(r.f1.size());
		r.recall = recallAt(a.outcomes, a.numGt, kRecallZ * object.diameter);
		r.medianTime = medianKnown(timeValues(a.times));
		if (vsd)
			r.arVsd = a.numGt ? a.vsdCorrect / static_cast<double>(a.numGt) : 0.0;
		report.objects.push_back(std::move(r));
	}

	const size_t n = report.objects.size();
	if (vsd)
		report.meanArVsd = 0;
	for (const ObjectEvalResult &r : report.objects) {
		for (size_t z = 0; z < zValues.size(); ++z)
			report.meanF1PerZ[z] += r.f1[z] / static_cast<double>(n);
		report.meanF1 += r.meanF1 / static_cast<double>(n);
		report.meanRecall += r.recall / static_cast<double>(n);
		if (vsd)
			report.meanArVsd += r.arVsd / static_cast<double>(n);
		report.numGt += r.numGt;
		report.numEstimates += r.numEstimates;
	}
	report.medianTime = medianKnown(timeValues(allTimes));
	return report;
}

} // namespace ihf
