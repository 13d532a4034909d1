// SPDX-License-Identifier: MIT
// The `ihf` executable: subcommands for synthesis, training, estimation,
// evaluation and the on-device loop.

#include <cstdio>

#include "firmware_app/commands/command.h"

int main(int argc, char **argv)
{
	using namespace ihf::app;

	CLI::App root{"ihf: 6D object pose from depth (Iterative Hough Forest, HoCP)", "ihf"};
	root.require_subcommand(1);
	root.set_version_flag("--version", "ihf 0.1.0");

	Action action;
	addSynthCommand(root, action);
	addTrainCommand(root, action);
	addEstimateCommand(root, action);
	addEvalCommand(root, action);
	addRenderCommand(root, action);
	addForestCommand(root, action);
	addRecordCommand(root, action);
	addRunCommand(root, action);
	addDevicesCommand(root, action);
	addConfigCommand(root, action);

	try {
		root.parse(argc, argv);
	} catch (const CLI::ParseError &e) {
		// --help and --version arrive here too, with exit code 0.
		return root.exit(e) == 0 ? kExitOk : kExitUsage;
	}
	if (!action) {
		std::fprintf(stderr, "ihf: no command chosen; see ihf --help\n");
		return kExitUsage;
	}
	return action();
}
