// SPDX-License-Identifier: MIT
#pragma once

// Each `ihf` subcommand lives in its own file and registers itself on the
// root CLI11 app. The action runs after parsing succeeded; it returns the
// process exit code: 0 success, 1 runtime failure (2 is a usage error and is
// produced by the parser).

#include <functional>

#include <CLI/CLI.hpp>

namespace ihf::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

using Action = std::function<int()>;

// Each registers a subcommand; `action` is set when that subcommand is chosen.
void addSynthCommand(CLI::App &root, Action &action);
void addEvalCommand(CLI::App &root, Action &action);
void addRenderCommand(CLI::App &root, Action &action);
void addForestCommand(CLI::App &root, Action &action);
void addTrainCommand(CLI::App &root, Action &action);
void addEstimateCommand(CLI::App &root, Action &action);
void addRecordCommand(CLI::App &root, Action &action);
void addRunCommand(CLI::App &root, Action &action);
void addDevicesCommand(CLI::App &root, Action &action);
void addConfigCommand(CLI::App &root, Action &action);

} // namespace ihf::app
