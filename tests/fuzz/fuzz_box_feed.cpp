// SPDX-License-Identifier: MIT
// The box lines of `ihf run` ({"frame": N, "boxes": [...]} per line) from a
// file: the feed is asked for frames 0..63 in turn, then for the last
// possible frame, which drains every line left.

#include <chrono>
#include <cstdint>
#include <limits>

#include "firmware_app/runtime/box_feed.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const auto file = ihf::fuzz::inputFile(data, size, "boxes.jsonl");
	auto feed = ihf::app::BoxFeed::open("file:" + file.string());
	if (!feed)
		return 0;
	for (uint64_t frame = 0; frame < 64; ++frame) {
		auto r = (*feed)->wait(frame, std::chrono::milliseconds(0));
		if (!r || *r == ihf::app::BoxWait::kEnd)
			return 0;
	}
	(void)(*feed)->wait(std::numeric_limits<uint64_t>::max(), std::chrono::milliseconds(0));
	return 0;
}
