// SPDX-License-Identifier: MIT
// The TOML configurations (config/train.toml, estimate.toml, device.toml):
// each input is read as all three.

#include "firmware_app/config/pipeline_config.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const auto file = ihf::fuzz::inputFile(data, size, "config.toml");
	(void)ihf::app::loadTrainConfig(file);
	(void)ihf::app::loadEstimateConfig(file);
	(void)ihf::app::loadRunConfig(file);
	return 0;
}
