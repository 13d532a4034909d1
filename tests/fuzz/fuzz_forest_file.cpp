// SPDX-License-Identifier: MIT
// The forest file (.ihf): loadModelFile and the `ihf forest info` summary.

#include "core/model/forest_file.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	auto summary = ihf::summariseModelFile(ihf::fuzz::inputFile(data, size, "forest.ihf"));
	if (summary)
		(void)ihf::formatForestFileSummary(*summary);
	return 0;
}
