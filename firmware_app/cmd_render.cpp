// SPDX-License-Identifier: MIT
#include "firmware_app/command.h"

namespace ihf::app {

void addRenderCommand(CLI::App &root, Action &action)
{
	auto *cmd = root.add_subcommand("render", "(being built)");
	cmd->callback([&action] { action = [] { return kExitFailure; }; });
}

} // namespace ihf::app
