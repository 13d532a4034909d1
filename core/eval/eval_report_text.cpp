// SPDX-License-Identifier: MIT
#include "core/eval/eval_report_text.h"

#include <cstdarg>
#include <cstdio>

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

} // namespace

std::string formatEvalTable(const EvalReport &report)
{
	std::string out;
	appendf(out, "F1 = best over confidence thresholds of 2PR/(P+R); correct iff error <= z*diameter\n");
	appendf(out, "%4s %-6s %8s %5s %5s", "obj", "metric", "diam/mm", "#gt", "#est");
	for (double z : report.zValues)
		appendf(out, " %5.2f", z);
	appendf(out, " %7s %7s %9s\n", "meanF1", "rec0.1d", "t_med/s");

	for (const ObjectEvalResult &r : report.objects) {
		appendf(out, "%4d %-6s %8.2f %5zu %5zu", r.objId, poseMetricName(r.metric),
			r.diameter, r.numGt, r.numEstimates);
		for (double f : r.f1)
			appendf(out, " %5.3f", f);
		appendf(out, " %7.4f %7.4f", r.meanF1, r.recall);
		appendTime(out, r.medianTime);
		out += '\n';
	}

	appendf(out, "%4s %-6s %8s %5zu %5zu", "mean", "", "", report.numGt, report.numEstimates);
	for (double f : report.meanF1PerZ)
		appendf(out, " %5.3f", f);
	appendf(out, " %7.4f %7.4f", report.meanF1, report.meanRecall);
	appendTime(out, report.medianTime);
	out += '\n';
	if (report.numIgnored)
		appendf(out, "%zu estimates outside the targets were ignored\n", report.numIgnored);
	return out;
}

} // namespace ihf
