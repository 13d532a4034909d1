// SPDX-License-Identifier: MIT
// The BOP JSON files and the detection boxes: every reader of core/dataset's
// bop_io.h that takes JSON is given each input (a corpus of one kind of file
// mutates into the others' shapes too).

#include "core/dataset/bop_io.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const auto file = ihf::fuzz::inputFile(data, size, "bop.json");
	(void)ihf::readBopCamera(file);
	(void)ihf::readModelsInfo(file);
	(void)ihf::readSceneCamera(file);
	(void)ihf::readSceneGt(file);
	(void)ihf::readSceneGtInfo(file);
	(void)ihf::readDetections(file);
	return 0;
}
