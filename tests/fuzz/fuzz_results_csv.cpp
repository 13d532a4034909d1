// SPDX-License-Identifier: MIT
// BOP results CSV (ihf eval): readResultsCsv.

#include "core/dataset/bop_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	(void)ihf::readResultsCsv(ihf::fuzz::inputFile(data, size, "results.csv"));
	return 0;
}
