// SPDX-License-Identifier: MIT
// The pose lines of `ihf run` as `ihf eval --run-poses` reads them:
// readRunPoses.

#include "core/eval/run_poses.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	(void)ihf::readRunPoses(ihf::fuzz::inputFile(data, size, "poses.jsonl"));
	return 0;
}
