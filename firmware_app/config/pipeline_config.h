// SPDX-License-Identifier: MIT
#pragma once

// The TOML configurations of `ihf train`, `ihf estimate` and `ihf run`
// (config/*.toml).
// Every key has a default in code; a file overrides some of them. Unknown
// keys and wrongly typed values are errors naming the file and the key, so a
// typo never silently falls back to a default.

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "core/common/expected.h"
#include "core/estimation/pose_estimator.h"
#include "core/training/view_template_builder.h"
#include "core/forest/forest_trainer.h"
#include "core/forest/forest_view.h"
#include "core/model/model_params.h"
#include "core/training/training_set.h"
#include "core/tracking/tracker_config.h"

namespace ihf::app {

// `ihf train`'s settings. Where they differ from the library's defaults
// (the paper's choices, which the core's tests train with), these are the
// measured better ones that config/train.toml ships (BENCHMARKS.md): fixed
// parts, three scales, occluded views.
struct TrainSettings {
	TrainSettings();
	ModelParams params;
	TrainingSetConfig set;
	ForestTrainerConfig forest;
	TemplateEncoding encoding = TemplateEncoding::kUint8;
};

// What the given boxes bound ([boxes] kind, `--box-kind`). The score's
// box factor and its occlusion weight are measured for one or the other:
// weights that gain with boxes round the whole object lose with boxes round
// its visible part (BENCHMARKS.md).
enum class BoxKind {
	kAmodal, // the whole object, hidden parts too (BOP's bbox_obj; the LM-O protocol)
	kModal,  // the visible part (BOP's bbox_visib; what most detectors give)
};

// "amodal" or "modal"; anything else is an error naming `what`.
Expected<BoxKind> parseBoxKind(const std::string &name, const std::string &what);
const char *boxKindName(BoxKind kind);

// The score weights that differ with the kind of box ([score] holds the
// amodal ones, [modal_boxes.score] the modal ones), and whether the view
// search places rotations by the box's size (only a box round the whole
// object tells its depth).
struct BoxKindWeights {
	float occludedWeight;
	float boxWeight;
	float boxOccludedSide;
	bool boxSizeSearch;
};

// Offline (`ihf estimate`) defaults to no frame budget, so that accuracy is
// that of the full method; `ihf run` without an estimation config runs on
// kDeviceFrameBudgetMs frames.
struct EstimateSettings {
	EstimatorConfig estimator;
	// The kind of the boxes the estimator is given ([boxes] kind), whose
	// weights estimator.score holds (useBoxKind).
	BoxKind boxKind = BoxKind::kAmodal;
	BoxKindWeights amodal{ScoreConfig{}.occludedWeight, ScoreConfig{}.boxWeight, ScoreConfig{}.boxOccludedSide,
			      ViewSearchConfig{}.boxSizeSearch};
	// Boxes round the visible part: a lighter occlusion weight, the box
	// factor to the power 1 and the sides the scene hides open to overhang
	// (the amodal weights lose with such boxes; BENCHMARKS.md).
	BoxKindWeights modal{0.2f, 1.0f, 0.5f, false};
	// The library runs one thread unless asked; the tool uses every core.
	EstimatorLimits limits = [] {
		EstimatorLimits l;
		l.threads = 0;
		return l;
	}();
	// Templates built at load for forest files written without them
	// ([view_search] viewpoints, points; budget_viewpoints when the
	// estimator has a frame budget).
	ViewTemplateConfig viewTemplates;
	// Hypotheses are rendered with the mesh simplified to this deviation
	// ([render_mesh] max_error_mm); 0: the full mesh.
	float renderMeshErrorMm = 0.5f;
};

// Sets boxKind and the estimator's score weights for boxes of that kind.
void useBoxKind(EstimateSettings &settings, BoxKind kind);

// Readies a loaded model for estimation. Gives it view templates when the
// view search is on and its file has none (forests trained before templates
// were stored: built from its mesh, about a second), and its simplified
// render mesh. Offline (allocates): call at start-up.
Status prepareModel(ObjectModel &model, const EstimateSettings &settings);

// Grows the estimator's limits to what a prepared model needs (its render
// mesh, IBS lattice, point budget and HoCP length), so one arena serves
// every model.
void growLimitsFor(EstimatorLimits &limits, const ObjectModel &model);

// `ihf run` (config/device.toml). Relative paths in the file (recording:
// URIs, forests, box and pose files, the estimation config) are relative to
// the folder of the file.
inline constexpr float kDeviceFrameBudgetMs = 33.0f;

struct RunSettings {
	// [source]
	std::string sourceUri;
	bool realTime = false; // recordings: paced by their timestamps, else stepped
	double speed = 1.0;
	int timeoutMs = 1000; // per next(); a live source silent this long is reported
	int maxRetries = 5; // reopen attempts in a row after a source error (0: none)
	int retryBackoffMs = 200; // wait before the first reopen, doubled each time
	int retryBackoffMaxMs = 5000;
	// USB watch: "" off, "any" known depth sensor, or "VID:PID". An unplugged
	// sensor is waited for (reported) instead of spending reopen attempts.
	std::string usbWatch;
	// [boxes]
	std::string boxes = "stdin"; // "stdin", "file:PATH" or "unix:PATH"
	int boxesTimeoutMs = 200; // live box inputs: wait for a frame's boxes
	// What the boxes bound ("amodal" or "modal"); none: as the estimation
	// config's [boxes] kind (a detector's boxes are usually modal).
	std::optional<BoxKind> boxKind;
	// [output]
	std::string poses = "stdout"; // "stdout", "file:PATH" or "socket" (the boxes' unix socket)
	// [objects] object id -> forest file
	std::map<int, std::filesystem::path> forests;
	// [estimate]
	std::filesystem::path estimateConfig; // empty: defaults
	std::optional<int> iterations; // instead of the estimation config's
	// The frame's estimation budget, instead of the estimation config's
	// (without one: kDeviceFrameBudgetMs).
	std::optional<double> estimationBudgetMs;
	// [tracking] frame-to-frame tracking (core/tracking); enabled = false:
	// every box a cold detection
	TrackerConfig tracking;
	// [run]
	double dropFramesOlderThanMs = 0; // real time: frames older than this at their turn are dropped; 0: never
	double statsIntervalS = 5; // periodic stats on stderr; 0: only at the end
	int64_t maxFrames = 0; // stop after this many frames delivered; 0: no limit
};

// An empty path gives the defaults.
Expected<TrainSettings> loadTrainConfig(const std::filesystem::path &path);
Expected<EstimateSettings> loadEstimateConfig(const std::filesystem::path &path);
// The paper's method alone (`ihf estimate --paper`): no ICP, view search or
// half-turns, and refinement iterations voting as the registration does.
void applyPapersMethod(EstimatorConfig &e);
Expected<RunSettings> loadRunConfig(const std::filesystem::path &path);

} // namespace ihf::app
