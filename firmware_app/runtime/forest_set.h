// SPDX-License-Identifier: MIT
#pragma once

// The forests a run knows, one per object id: parsed from `--forest
// OBJ_ID=FILE` or the [objects] table of a device configuration, loaded,
// prepared for the estimation settings (view templates, render mesh) and
// counted into the estimator's limits. The one loading path of
// `ihf estimate` and `ihf run`.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "core/model/object_model.h"
#include "firmware_app/config/pipeline_config.h"

namespace ihf::app {

// "OBJ_ID=FILE" options into an id -> file map; an error names the
// option that is not of that form, or an id given twice.
Expected<std::map<int, std::filesystem::path>> parseForestOptions(const std::vector<std::string> &specs);

class ForestSet
{
public:
	// Loads each file, prepares it for `settings` and grows settings.limits
	// to hold it. A file trained for another object id than it is given
	// for is used as given, with a note on stderr (prefixed `command`).
	static Expected<ForestSet> load(const std::map<int, std::filesystem::path> &forests,
					EstimateSettings &settings, const char *command);

	// The models by object id (owned by the set).
	const std::map<int, const ObjectModel *> &models() const { return models_; }
	const ObjectModel *find(int objId) const;

private:
	std::vector<std::unique_ptr<ObjectModel>> owned_;
	std::map<int, const ObjectModel *> models_;
};

} // namespace ihf::app
