// SPDX-License-Identifier: MIT
#include "core/eval/eval_report_text.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <vector>

namespace ihf {

namespace {

void appendf(std::string &out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

void appendf(std::string &out, const char *fmt, ...)
{
	char buf[256];
	va_list args;
	va_start(args, fmt);
	std::vsnprintf(buf, sizeof(buf), fmt, args);
	va_end(args);
	out += buf;
}

void appendTime(std::string &out, double seconds)
{
	if (seconds < 0)
		appendf(out, " %9s", "-");
	else
		appendf(out, " %9.4f", seconds);
}

// A column of `width` after a space; "-" for a value that is not there.
void appendOptional(std::string &out, int width, bool present, unsigned long long value)
{
	if (present)
		appendf(out, " %*llu", width, value);
	else
		appendf(out, " %*s", width, "-");
}

const char *verdictName(RunPoseVerdict verdict)
{
	switch (verdict) {
	case RunPoseVerdict::kRight: return "right";
	case RunPoseVerdict::kWrong: return "wrong";
	case RunPoseVerdict::kNoPose: return "no pose";
	case RunPoseVerdict::kNoTruth: return "no truth";
	}
	return "?";
}

void appendRunPoseRow(std::string &out, const RunPoseCheck &c)
{
	appendf(out, "%5zu", c.line);
	appendOptional(out, 6, c.frame.has_value(), c.frame.value_or(0));
	appendOptional(out, 5, c.sceneId >= 0, static_cast<unsigned>(c.sceneId));
	appendOptional(out, 5, c.imageId >= 0, static_cast<unsigned>(c.imageId));
	appendOptional(out, 4, c.objId.has_value(), static_cast<unsigned>(c.objId.value_or(0)));
	if (c.verdict == RunPoseVerdict::kRight || c.verdict == RunPoseVerdict::kWrong) {
		appendf(out, " %8.2f %9.2f %-6s %6.3f  %s\n", c.rotationDeg, c.translationMm,
			poseMetricName(c.metric), c.errorShare, verdictName(c.verdict));
		return;
	}
	appendf(out, " %8s %9s %-6s %6s  %s: ", "-", "-", "-", "-", verdictName(c.verdict));
	out += c.note; // may be longer than appendf's buffer
	out += '\n';
}

// "4 of 4 poses right (ADD <= 0.1 d); rotation error median ..., max ...; translation ..."
void appendRunPoseSummary(std::string &out, const RunPoseReport &report)
{
	std::vector<double> rotations, translations;
	size_t right = 0, noPose = 0, noTruth = 0;
	bool add = false, adi = false;
	for (const RunPoseCheck &c : report.checks) {
		noPose += c.verdict == RunPoseVerdict::kNoPose;
		noTruth += c.verdict == RunPoseVerdict::kNoTruth;
		if (c.verdict != RunPoseVerdict::kRight && c.verdict != RunPoseVerdict::kWrong)
			continue;
		right += c.verdict == RunPoseVerdict::kRight;
		rotations.push_back(c.rotationDeg);
		translations.push_back(c.translationMm);
		(c.metric == PoseMetric::kAdi ? adi : add) = true;
	}
	const char *metric = add && adi ? "ADD/ADI" : (adi ? "ADI" : "ADD");
	appendf(out, "%zu of %zu poses right (%s <= %g d)", right, rotations.size(), metric,
		report.threshold);
	if (noPose)
		appendf(out, ", %zu line%s without a pose", noPose, noPose == 1 ? "" : "s");
	if (noTruth)
		appendf(out, ", %zu pose%s without ground truth", noTruth, noTruth == 1 ? "" : "s");
	if (!rotations.empty())
		appendf(out, "; rotation error median %.2f deg, max %.2f; translation median %.2f mm, max %.2f",
			medianKnown(rotations), *std::max_element(rotations.begin(), rotations.end()),
			medianKnown(translations), *std::max_element(translations.begin(), translations.end()));
	out += '\n';
}

} // namespace

std::string formatRunPoseTable(const RunPoseReport &report)
{
	std::string out;
	appendf(out, "%5s %6s %5s %5s %4s %8s %9s %-6s %6s  %s\n", "line", "frame", "scene", "image", "obj",
		"rot/deg", "trans/mm", "metric", "err/d", "verdict");
	for (const RunPoseCheck &c : report.checks)
		appendRunPoseRow(out, c);
	appendRunPoseSummary(out, report);
	return out;
}

std::string formatEvalTable(const EvalReport &report)
{
	std::string out;
	appendf(out, "F1 = best over confidence thresholds of 2PR/(P+R); correct iff error <= z*diameter\n");
	appendf(out, "%4s %-6s %8s %5s %5s", "obj", "metric", "diam/mm", "#gt", "#est");
	for (double z : report.zValues)
		appendf(out, " %5.2f", z);
	appendf(out, " %7s %7s", "meanF1", "rec0.1d");
	const bool vsd = report.meanArVsd >= 0;
	if (vsd)
		appendf(out, " %7s", "AR_VSD");
	appendf(out, " %9s\n", "t_med/s");

	for (const ObjectEvalResult &r : report.objects) {
		appendf(out, "%4d %-6s %8.2f %5zu %5zu", r.objId, poseMetricName(r.metric),
			r.diameter, r.numGt, r.numEstimates);
		for (double f : r.f1)
			appendf(out, " %5.3f", f);
		appendf(out, " %7.4f %7.4f", r.meanF1, r.recall);
		if (vsd)
			appendf(out, " %7.4f", r.arVsd);
		appendTime(out, r.medianTime);
		out += '\n';
	}

	appendf(out, "%4s %-6s %8s %5zu %5zu", "mean", "", "", report.numGt, report.numEstimates);
	for (double f : report.meanF1PerZ)
		appendf(out, " %5.3f", f);
	appendf(out, " %7.4f %7.4f", report.meanF1, report.meanRecall);
	if (vsd)
		appendf(out, " %7.4f", report.meanArVsd);
	appendTime(out, report.medianTime);
	out += '\n';
	if (report.numIgnored)
		appendf(out, "%zu estimates outside the targets were ignored\n", report.numIgnored);
	return out;
}

} // namespace ihf
