// SPDX-License-Identifier: MIT
// `ihf config`: the effective configuration (after the given files), each
// key with its value, default and meaning; --markdown: the reference of
// every key (docs/configuration.md).

#include <cstdio>
#include <memory>
#include <string>

#include "firmware_app/commands/command.h"
#include "firmware_app/config/config_reference.h"
#include "firmware_app/config/pipeline_config.h"

namespace ihf::app {

namespace {

struct ConfigOptions {
	std::string estimate, train, device, only;
	bool markdown = false;
};

bool printOne(const Schema &schema, const std::string &path)
{
	SettingsOf settings(schema);
	if (Status st = schema.load(path, settings.get()); !st) {
		std::fprintf(stderr, "ihf config: %s\n", st.error().message.c_str());
		return false;
	}
	const std::string text = effectiveConfig(schema, settings.get(), path.empty() ? "defaults" : path);
	std::fputs(text.c_str(), stdout);
	return true;
}

int runConfig(const ConfigOptions &o)
{
	if (o.markdown) {
		std::fputs(configurationMarkdown().c_str(), stdout);
		return kExitOk;
	}
	const std::string files[] = {o.estimate, o.train, o.device};
	bool ok = true, first = true;
	for (size_t i = 0; i < schemas().size(); ++i) {
		const Schema &schema = *schemas()[i];
		if (!o.only.empty() && o.only != schema.kind)
			continue;
		if (!first)
			std::fputs("\n", stdout);
		first = false;
		ok = printOne(schema, files[i]) && ok;
	}
	return ok ? kExitOk : kExitFailure;
}

} // namespace

void addConfigCommand(CLI::App &root, Action &action)
{
	auto opts = std::make_shared<ConfigOptions>();
	CLI::App *cmd = root.add_subcommand(
		"config", "Print the effective configuration (each key's value, default and meaning), or the reference");
	cmd->add_option("--estimate", opts->estimate, "estimation config (ihf estimate --config); none: the defaults");
	cmd->add_option("--train", opts->train, "training config (ihf train --config); none: the defaults");
	cmd->add_option("--device", opts->device, "device config (ihf run --config); none: the defaults");
	cmd->add_option("--only", opts->only, "print only this configuration")
		->check(CLI::IsMember({"estimate", "train", "device"}));
	cmd->add_flag("--markdown", opts->markdown,
		      "print the reference of every key as Markdown (docs/configuration.md)");
	cmd->callback([opts, &action] { action = [opts] { return runConfig(*opts); }; });
}

} // namespace ihf::app
