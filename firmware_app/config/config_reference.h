// SPDX-License-Identifier: MIT
#pragma once

// The configuration as text: the effective settings of one configuration
// with each key's default and meaning (`ihf config`), and the reference of
// every key of the three (`ihf config --markdown`, docs/configuration.md).

#include <string>

#include "firmware_app/config/config_schema.h"

namespace ihf::app {

// The settings (of the schema's kind) as TOML, every key with its meaning,
// and its default where the value differs; `source` names where they came
// from.
std::string effectiveConfig(const Schema &schema, void *settings, const std::string &source);

// docs/configuration.md.
std::string configurationMarkdown();

} // namespace ihf::app
