// SPDX-License-Identifier: MIT
// Recordings (.rec): RecordingReader::open, then every frame read.

#include <vector>

#include "drivers/recording_reader.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	auto reader = ihf::RecordingReader::open(ihf::fuzz::inputFile(data, size, "frames.rec"));
	if (!reader)
		return 0;
	const auto &k = reader->header().intrinsics;
	std::vector<uint16_t> pixels(static_cast<size_t>(k.width) * k.height);
	ihf::ImageView<uint16_t> depth(pixels.data(), k.width, k.height);
	for (size_t i = 0; i < reader->frameCount(); ++i) {
		ihf::recording::FrameRecord record;
		(void)reader->read(i, record, depth);
		(void)reader->find(reader->entry(i).frameIndex);
	}
	return 0;
}
