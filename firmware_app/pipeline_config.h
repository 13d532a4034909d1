// SPDX-License-Identifier: MIT
#pragma once

// The TOML configurations of `ihf train` and `ihf estimate` (config/*.toml).
// Every key has a default in code; a file overrides some of them. Unknown
// keys and wrongly typed values are errors naming the file and the key, so a
// typo never silently falls back to a default.

#include <filesystem>

#include "core/common/expected.h"
#include "core/estimation/pose_estimator.h"
#include "core/forest/forest_trainer.h"
#include "core/forest/forest_view.h"
#include "core/model/model_params.h"
#include "core/training/training_set.h"

namespace ihf::app {

struct TrainSettings {
	ModelParams params;
	TrainingSetConfig set;
	ForestTrainerConfig forest;
	TemplateEncoding encoding = TemplateEncoding::kUint8;
};

struct EstimateSettings {
	// The pipeline runs under a frame budget by default; the library's
	// default is unlimited (so its tests do not depend on the machine).
	EstimateSettings() { estimator.frameBudgetMs = 33.0f; }

	EstimatorConfig estimator;
	EstimatorLimits limits;
};

// An empty path gives the defaults.
Expected<TrainSettings> loadTrainConfig(const std::filesystem::path &path);
Expected<EstimateSettings> loadEstimateConfig(const std::filesystem::path &path);

} // namespace ihf::app
