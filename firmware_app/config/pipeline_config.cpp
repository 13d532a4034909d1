// SPDX-License-Identifier: MIT
#include "firmware_app/config/pipeline_config.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <set>
#include <string>

#include "core/geometry/mesh_simplify.h"
#include "firmware_app/config/config_schema.h"

namespace ihf::app {

TrainSettings::TrainSettings()
{
	set.views.viewpoints = 160;
	set.views.inplaneSteps = 12;
	set.scales = {1.0f, 1.5f, 2.2f};
	set.partsPerImage = 6;
	set.occludedViews = 0.5f;
	params.parts.kind = PartKind::kFixed;
	params.parts.maxControlPoints = 128;
}

Expected<TrainSettings> loadTrainConfig(const std::filesystem::path &path)
{
	TrainSettings s;
	if (path.empty())
		return s;
	if (Status st = readConfigFile(path, trainSchema(), &s); !st)
		return st.error();
	if (std::string problem = hocpBinsProblem(s.params.hocp); !problem.empty())
		return makeError(Errc::kOutOfRange, path.string() + ": hocp: " + problem);
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
	settings.estimator.views.boxSizeSearch = w.boxSizeSearch;
}

void applyPapersMethod(EstimatorConfig &e)
{
	e.icp = false;
	e.views.inplane = 0;
	e.halfTurns.candidates = 0;
	e.symmetryTurns.enabled = false;
	iterationsAsRegistration(e);
}

Expected<EstimateSettings> loadEstimateConfig(const std::filesystem::path &path)
{
	EstimateSettings s;
	if (path.empty())
		return s;
	if (Status st = readConfigFile(path, estimateSchema(), &s); !st)
		return st.error();
	if (!(s.estimator.psi2 >= s.estimator.psi1))
		return makeError(Errc::kParse, path.string() + ": refinement.psi1/psi2: out of range (psi2 >= psi1)");
	useBoxKind(s, s.boxKind);
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
	const std::string file = path.string();
	const std::filesystem::path base = path.parent_path();
	// [objects]: object id -> forest file.
	const auto object = [&](const std::string &, const std::string &key,
				const std::optional<std::string> &forest) -> Status {
		int id = -1;
		try {
			size_t used = 0;
			id = std::stoi(key, &used);
			if (used != key.size())
				id = -1;
		} catch (...) {
		}
		if (id < 0)
			return makeError(Errc::kParse, file + ": objects." + key + ": keys are object ids (\"20\" = \"bunny.ihf\")");
		if (!forest)
			return makeError(Errc::kParse, file + ": objects." + key + ": expected a forest file path");
		const std::filesystem::path f = *forest;
		s.forests[id] = f.is_relative() ? (base / f).lexically_normal() : f;
		return {};
	};
	if (Status st = readConfigFile(path, deviceSchema(), &s, object); !st)
		return st.error();
	if (s.retryBackoffMaxMs < s.retryBackoffMs)
		return makeError(Errc::kParse, file + ": source.retry_backoff_max_ms: out of range (>= retry_backoff_ms)");
	if (!s.estimateConfig.empty() && s.estimateConfig.is_relative())
		s.estimateConfig = (base / s.estimateConfig).lexically_normal();
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
