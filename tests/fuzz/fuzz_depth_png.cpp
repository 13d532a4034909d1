// SPDX-License-Identifier: MIT
// BOP depth images (16-bit PNG): readDepthPng.

#include "core/dataset/bop_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	(void)ihf::readDepthPng(ihf::fuzz::inputFile(data, size, "depth.png"));
	return 0;
}
