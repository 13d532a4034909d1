// SPDX-License-Identifier: MIT
#pragma once

// A small recording for the run-loop tests: n flat 16 x 12 frames, indices
// 0..n-1, stamps 1/30 s apart.

#include <cstdint>
#include <filesystem>

#include <gtest/gtest.h>

#include "core/common/image.h"
#include "drivers/recording_format.h"
#include "drivers/recording_writer.h"

namespace ihf::test {

inline void writeSmallRecording(const std::filesystem::path &file, int n, const char *sensorId)
{
	recording::RecordingHeader h;
	h.sensorId = sensorId;
	h.intrinsics = CameraIntrinsics{500, 500, 7.5, 5.5, 16, 12};
	auto w = RecordingWriter::create(file, h);
	ASSERT_TRUE(w.ok()) << w.error().message;
	Image<uint16_t> depth(16, 12, 1000);
	for (int i = 0; i < n; ++i) {
		const int64_t t = static_cast<int64_t>(i) * 1'000'000'000 / 30;
		ASSERT_TRUE(w->append({static_cast<uint64_t>(i), t, t}, depth.view()).ok());
	}
	ASSERT_TRUE(w->finish().ok());
}

} // namespace ihf::test
