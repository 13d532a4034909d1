// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/forest_set.h"

#include <cstdio>

#include "core/model/forest_file.h"

namespace ihf::app {

Expected<std::map<int, std::filesystem::path>> parseForestOptions(const std::vector<std::string> &specs)
{
	std::map<int, std::filesystem::path> out;
	for (const std::string &spec : specs) {
		const size_t eq = spec.find('=');
		int id = -1;
		try {
			id = eq == std::string::npos ? -1 : std::stoi(spec.substr(0, eq));
		} catch (...) {
		}
		if (id < 0 || eq + 1 >= spec.size())
			return makeError(Errc::kInvalidArgument, "--forest expects OBJ_ID=FILE, got \"" + spec + "\"");
		if (!out.emplace(id, spec.substr(eq + 1)).second)
			return makeError(Errc::kInvalidArgument,
					 "--forest gives object " + std::to_string(id) + " twice (\"" + spec + "\")");
	}
	return out;
}

Expected<ForestSet> ForestSet::load(const std::map<int, std::filesystem::path> &forests, EstimateSettings &settings,
				    const char *command)
{
	ForestSet set;
	for (const auto &[id, file] : forests) {
		auto m = loadModelFile(file);
		if (!m)
			return m.error();
		if ((*m)->params().objId != id)
			std::fprintf(stderr, "%s: note: %s was trained as object %d, used for %d\n", command,
				     file.string().c_str(), (*m)->params().objId, id);
		if (Status st = prepareModel(**m, settings); !st)
			return makeError(st.error().code, file.string() + ": " + std::string(st.error().message));
		growLimitsFor(settings.limits, **m); // the estimator is sized for every model
		set.models_[id] = m->get();
		set.owned_.push_back(std::move(m.value()));
	}
	return set;
}

const ObjectModel *ForestSet::find(int objId) const
{
	const auto it = models_.find(objId);
	return it == models_.end() ? nullptr : it->second;
}

} // namespace ihf::app
