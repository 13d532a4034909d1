// SPDX-License-Identifier: MIT
// `ihf forest info F.ihf`: loads a forest file with full validation and
// prints its header, section table, per-tree statistics, mesh and training
// parameters. A damaged file fails with the loader's message.

#include <cstdio>
#include <memory>
#include <string>

#include "core/model/forest_file.h"
#include "firmware_app/commands/command.h"

namespace ihf::app {

namespace {

int runForestInfo(const std::string &file)
{
	Expected<ForestFileSummary> summary = summariseModelFile(file);
	if (!summary) {
		std::fprintf(stderr, "ihf forest info: %s\n", summary.error().message.c_str());
		return kExitFailure;
	}
	std::fputs(formatForestFileSummary(*summary).c_str(), stdout);
	return kExitOk;
}

} // namespace

void addForestCommand(CLI::App &root, Action &action)
{
	auto *cmd = root.add_subcommand("forest", "Inspect trained forest files (.ihf)");
	cmd->require_subcommand(1);

	auto file = std::make_shared<std::string>();
	auto *info = cmd->add_subcommand(
		"info", "Validate a forest file and print its sections, CRCs, trees (nodes, leaves, "
			"depth, votes), mesh and parameters");
	info->add_option("file", *file, "forest file (.ihf)")->required();
	info->callback([&action, file] { action = [file] { return runForestInfo(*file); }; });
}

} // namespace ihf::app
