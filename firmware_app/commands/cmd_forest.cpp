// SPDX-License-Identifier: MIT
// `ihf forest info F.ihf`: loads a forest file with full validation and
// prints its header, section table, per-tree statistics, mesh, near-
// symmetries and training parameters. A damaged file fails with the
// loader's message. `ihf forest symmetries IN --out OUT`: the forest with the
// near-symmetries of its mesh found as `ihf train` finds them, for a forest
// trained without them (version 2), so that it need not be trained again.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/model/forest_file.h"
#include "core/training/near_symmetry_finder.h"
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

int runForestSymmetries(const std::string &in, const std::string &out)
{
	Expected<std::unique_ptr<ObjectModel>> model = loadModelFile(in);
	if (!model) {
		std::fprintf(stderr, "ihf forest symmetries: %s\n", model.error().message.c_str());
		return kExitFailure;
	}
	const ObjectModel &m = **model;
	const std::vector<NearSymmetry> found = findNearSymmetries(m.mesh());
	if (Status s = saveModelFile(out, m.params(), m.mesh(), m.forest(), found); !s) {
		std::fprintf(stderr, "ihf forest symmetries: %s\n", s.error().message.c_str());
		return kExitFailure;
	}
	for (const NearSymmetry &ns : found)
		std::fprintf(stderr, "ihf forest symmetries: %s\n", describeNearSymmetry(ns).c_str());
	std::fprintf(stderr, "ihf forest symmetries: %zu near-symmetries; wrote %s\n", found.size(), out.c_str());
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

	auto in = std::make_shared<std::string>();
	auto out = std::make_shared<std::string>();
	auto *symmetries = cmd->add_subcommand(
		"symmetries", "Find the near-symmetries of a forest's object as ihf train does (turns that map all but "
			      "a small part onto itself) and write the forest with them");
	symmetries->add_option("file", *in, "forest file (.ihf)")->required();
	symmetries->add_option("--out", *out, "the forest with its near-symmetries (may be the input)")->required();
	symmetries->callback([&action, in, out] { action = [in, out] { return runForestSymmetries(*in, *out); }; });
}

} // namespace ihf::app
