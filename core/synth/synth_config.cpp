// SPDX-License-Identifier: MIT
#include "core/synth/synth_config.h"

#include <charconv>
#include <cmath>
#include <set>

namespace ihf {

namespace {

bool parseDouble(const std::string &s, double &v)
{
	if (s.empty())
		return false;
	const char *end = s.data() + s.size();
	auto r = std::from_chars(s.data(), end, v);
	return r.ec == std::errc() && r.ptr == end && std::isfinite(v);
}

} // namespace

Expected<std::pair<double, double>> parseRange(const std::string &text, const std::string &flag)
{
	const auto colon = text.find(':');
	double a, b;
	if (colon == std::string::npos) {
		if (!parseDouble(text, a))
			return makeError(Errc::kInvalidArgument, flag + " '" + text + "': expected MIN:MAX");
		return std::pair{a, a};
	}
	if (!parseDouble(text.substr(0, colon), a) || !parseDouble(text.substr(colon + 1), b))
		return makeError(Errc::kInvalidArgument, flag + " '" + text + "': expected MIN:MAX");
	if (a > b)
		return makeError(Errc::kInvalidArgument,
				 flag + " '" + text + "': MIN is larger than MAX");
	return std::pair{a, b};
}

Expected<std::vector<int>> parseIdList(const std::string &text, const std::string &flag)
{
	std::vector<int> ids;
	std::set<int> seen;
	size_t start = 0;
	while (start <= text.size()) {
		const size_t comma = std::min(text.find(',', start), text.size());
		const std::string item = text.substr(start, comma - start);
		int v = 0;
		auto r = std::from_chars(item.data(), item.data() + item.size(), v);
		if (item.empty() || r.ec != std::errc() || r.ptr != item.data() + item.size() || v <= 0)
			return makeError(Errc::kInvalidArgument,
					 flag + " '" + text + "': '" + item + "' is not a positive object id");
		if (!seen.insert(v).second)
			return makeError(Errc::kInvalidArgument,
					 flag + " '" + text + "': object id " + item + " repeated");
		ids.push_back(v);
		start = comma + 1;
	}
	return ids;
}

Status validateConfig(const SynthConfig &c)
{
	const SynthParams &p = c.params;
	auto bad = [](const std::string &m) { return Status(makeError(Errc::kInvalidArgument, m)); };
	if (c.modelsDir.empty())
		return bad("--models: no models folder given");
	if (c.outDir.empty())
		return bad("--out: no output folder given");
	if (c.objects.empty())
		return bad("--objects: no object id given");
	if (c.images < 1 || c.images > 100000)
		return bad("--images " + std::to_string(c.images) + ": must be 1..100000");
	if (p.layout.distanceMin < 300 || p.layout.distanceMax > 3500 ||
	    p.layout.distanceMin > p.layout.distanceMax)
		return bad("--distance: must lie within 300:3500 mm with MIN <= MAX");
	if (p.occlusionMin < 0 || p.occlusionMax > 0.95 || p.occlusionMin > p.occlusionMax)
		return bad("--occlusion: must lie within 0:0.95 with MIN <= MAX");
	// Pixel counts cannot hit a single value; 0:0 (fully visible) they can.
	if (p.occlusionMax > 0 && p.occlusionMax - p.occlusionMin < 0.02)
		return bad("--occlusion: the range must be at least 0.02 wide (or 0:0)");
	if (p.layout.elevationMinDeg < 5 || p.layout.elevationMaxDeg > 85 ||
	    p.layout.elevationMinDeg > p.layout.elevationMaxDeg)
		return bad("--elevation: must lie within 5:85 degrees with MIN <= MAX");
	if (p.layout.clutterMin < 0 || p.layout.clutterMax > 30 ||
	    p.layout.clutterMin > p.layout.clutterMax)
		return bad("--clutter: must lie within 0:30 with MIN <= MAX");
	if (p.layout.wallProbability < 0 || p.layout.wallProbability > 1)
		return bad("--wall: probability must be in [0, 1]");
	if (!(p.depthScale == 1.0 || p.depthScale == 0.1))
		return bad("--depth-scale: must be 1 (mm) or 0.1 (0.1 mm)");
	if (c.previewCount < 0)
		return bad("--preview-count: must be >= 0");
	std::error_code ec;
	const auto outAbs = std::filesystem::weakly_canonical(c.outDir, ec);
	const auto modelsAbs = std::filesystem::weakly_canonical(c.modelsDir, ec);
	if (!ec && outAbs == modelsAbs)
		return bad("--out: must differ from --models");
	return {};
}

} // namespace ihf
