// SPDX-License-Identifier: MIT
#pragma once

// Known frames for the recording tests: a seeded pseudo-random depth map
// with holes, the extremes 0 and 65535, and a smooth ramp (compressible).

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/common/image.h"
#include "drivers/recording_format.h"
#include "drivers/recording_writer.h"

namespace ihf::test {

inline recording::RecordingHeader testHeader(int w = 64, int h = 48)
{
	recording::RecordingHeader hd;
	hd.sensorId = "test sensor #7";
	hd.intrinsics = CameraIntrinsics{525.25, 526.5, 31.75, 23.5, w, h};
	hd.depthScale = 0.1;
	return hd;
}

inline DepthImage16 testFrame(int w, int h, uint32_t seed)
{
	DepthImage16 img(w, h);
	std::mt19937 rng(seed);
	std::uniform_int_distribution<int> noise(-20, 20);
	for (int y = 0; y < h; ++y)
		for (int x = 0; x < w; ++x)
			img.at(x, y) = static_cast<uint16_t>(800 + 3 * x + 2 * y + noise(rng) + 40 * seed);
	img.at(0, 0) = 0;
	img.at(1, 0) = 65535;
	img.at(w - 1, h - 1) = 0x1234;
	return img;
}

struct TestStream {
	std::vector<uint64_t> indices;
	std::vector<int64_t> deviceNs;
	std::vector<int64_t> hostNs;
	std::vector<DepthImage16> frames;
};

// Five frames, indices 10 11 12 14 15 (one dropped), 33 ms apart.
inline TestStream testStream(int w = 64, int h = 48)
{
	TestStream s;
	s.indices = {10, 11, 12, 14, 15};
	for (size_t i = 0; i < s.indices.size(); ++i) {
		s.deviceNs.push_back(1'000'000'000LL + static_cast<int64_t>(s.indices[i]) * 33'000'000LL);
		s.hostNs.push_back(5'000'000'000LL + static_cast<int64_t>(s.indices[i]) * 33'333'333LL + 7);
		s.frames.push_back(testFrame(w, h, static_cast<uint32_t>(i + 1)));
	}
	return s;
}

inline void writeStream(const std::filesystem::path &file, const TestStream &s, bool compress,
			const recording::RecordingHeader &header = testHeader())
{
	RecordingWriterOptions o;
	o.compress = compress;
	auto w = RecordingWriter::create(file, header, o);
	ASSERT_TRUE(w.ok()) << w.error().message;
	for (size_t i = 0; i < s.frames.size(); ++i) {
		Status st = w->append({s.indices[i], s.deviceNs[i], s.hostNs[i]}, s.frames[i].view());
		ASSERT_TRUE(st.ok()) << st.error().message;
	}
	Status st = w->finish();
	ASSERT_TRUE(st.ok()) << st.error().message;
}

inline std::vector<uint8_t> readBytes(const std::filesystem::path &file)
{
	std::ifstream in(file, std::ios::binary);
	return {std::istreambuf_iterator<char>(in), {}};
}

inline void writeBytes(const std::filesystem::path &file, const std::vector<uint8_t> &bytes)
{
	std::ofstream out(file, std::ios::binary | std::ios::trunc);
	out.write(reinterpret_cast<const char *>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// "" when equal, else where and how the first difference is.
inline std::string depthDifference(ImageView<const uint16_t> a, const DepthImage16 &b)
{
	if (a.width != b.width() || a.height != b.height())
		return "size " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
		       std::to_string(b.width()) + "x" + std::to_string(b.height());
	int count = 0;
	std::string first;
	for (int y = 0; y < a.height; ++y)
		for (int x = 0; x < a.width; ++x)
			if (a.at(x, y) != b.at(x, y) && count++ == 0)
				first = "(" + std::to_string(x) + ", " + std::to_string(y) + "): " +
					std::to_string(a.at(x, y)) + " vs " + std::to_string(b.at(x, y));
	return count ? std::to_string(count) + " pixels differ, first at " + first : "";
}

inline bool sameDepth(ImageView<const uint16_t> a, const DepthImage16 &b)
{
	if (a.width != b.width() || a.height != b.height())
		return false;
	for (int y = 0; y < a.height; ++y)
		for (int x = 0; x < a.width; ++x)
			if (a.at(x, y) != b.at(x, y))
				return false;
	return true;
}

} // namespace ihf::test
