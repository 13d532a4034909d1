// SPDX-License-Identifier: MIT
#pragma once

// The .rec recording file, version 1 (docs/recording.md has the full
// layout). Every integer and double is explicitly little-endian:
//
//   header   magic "IHFREC\x1a\n", version, header size, width, height,
//            fx fy cx cy depth_scale (f64), sensor id, header CRC32
//   frames   "IHFF", encoding, frame index, device ns, host ns,
//            payload size, CRC32 (of the 36 bytes before it + payload),
//            payload (raw uint16 depth rows, or zlib of them)
//   index    "IHFX", count, count x (frame index u64, file offset u64)
//   footer   index offset u64, index CRC32, "IHFE"
//
// A file without a valid index/footer (truncated, or its writer died) is
// still readable by scanning the frame records from the header on.

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "core/geometry/camera_intrinsics.h"

namespace ihf::recording {

inline constexpr std::array<uint8_t, 8> kFileMagic = {'I', 'H', 'F', 'R', 'E', 'C', 0x1a, '\n'};
inline constexpr uint32_t kVersion = 1;
inline constexpr uint32_t kFrameMagic = 0x46464849; // "IHFF"
inline constexpr uint32_t kIndexMagic = 0x58464849; // "IHFX"
inline constexpr uint32_t kFooterMagic = 0x45464849; // "IHFE"

// Header bytes before the sensor id, and the limit on the id.
inline constexpr size_t kHeaderFixedSize = 8 + 4 + 4 + 4 + 4 + 5 * 8 + 4;
inline constexpr size_t kMaxSensorIdSize = 1024;
inline constexpr size_t kFrameHeaderSize = 4 + 4 + 8 + 8 + 8 + 4 + 4; // 40
inline constexpr size_t kFrameCrcOffset = 36;
inline constexpr size_t kIndexEntrySize = 16;
inline constexpr size_t kFooterSize = 16;
inline constexpr int kMaxDimension = 16384;

enum class Encoding : uint32_t {
	kRaw = 0, // width * height uint16 little-endian, row-major, no padding
	kZlib = 1, // the raw payload, zlib (RFC 1950) compressed
};

// What a recording says about its sensor; the same for every frame.
struct RecordingHeader {
	uint32_t version = kVersion;
	std::string sensorId;
	CameraIntrinsics intrinsics; // width/height = frame size
	double depthScale = 1.0; // raw * depthScale = millimetres
};

// The per-frame fields stored before each payload.
struct FrameRecord {
	Encoding encoding = Encoding::kRaw;
	uint64_t index = 0;
	int64_t deviceTimestampNs = 0;
	int64_t hostTimestampNs = 0;
	uint32_t payloadSize = 0;
	uint32_t crc = 0;
};

struct IndexEntry {
	uint64_t frameIndex = 0;
	uint64_t offset = 0; // of the frame record from the start of the file
};

// Little-endian field access over byte buffers.
inline void putU32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		p[i] = static_cast<uint8_t>(v >> (8 * i));
}

inline void putU64(uint8_t *p, uint64_t v)
{
	for (int i = 0; i < 8; ++i)
		p[i] = static_cast<uint8_t>(v >> (8 * i));
}

inline void putF64(uint8_t *p, double v) { putU64(p, std::bit_cast<uint64_t>(v)); }

inline uint32_t getU32(const uint8_t *p)
{
	uint32_t v = 0;
	for (int i = 0; i < 4; ++i)
		v |= static_cast<uint32_t>(p[i]) << (8 * i);
	return v;
}

inline uint64_t getU64(const uint8_t *p)
{
	uint64_t v = 0;
	for (int i = 0; i < 8; ++i)
		v |= static_cast<uint64_t>(p[i]) << (8 * i);
	return v;
}

inline double getF64(const uint8_t *p) { return std::bit_cast<double>(getU64(p)); }

uint32_t crc32Of(std::span<const uint8_t> bytes, uint32_t crc = 0);

// Serialised header (with its CRC); fails on an invalid header.
Expected<std::vector<uint8_t>> encodeHeader(const RecordingHeader &header);

// Parses and validates a header from the start of a file; headerSize gets the
// number of bytes it occupies. source names the file in error messages.
Expected<RecordingHeader> decodeHeader(std::span<const uint8_t> bytes, const std::string &source,
				       size_t *headerSize);

void encodeFrameRecord(const FrameRecord &record, uint8_t *out);
FrameRecord decodeFrameRecord(const uint8_t *in);

// The CRC a frame record must carry: over its first 36 bytes and the payload.
uint32_t frameCrc(const uint8_t *recordHeader, std::span<const uint8_t> payload);

// zlib streams kept for a whole recording: set up once, reset per frame, so
// compressing or inflating a frame does not allocate.
struct ZlibStreams;
struct ZlibStreamsDeleter {
	void operator()(ZlibStreams *z) const;
};
using ZlibStreamsPtr = std::unique_ptr<ZlibStreams, ZlibStreamsDeleter>;

ZlibStreamsPtr makeInflater();
ZlibStreamsPtr makeDeflater(int level);
// Upper bound of a deflated raw frame of rawBytes.
size_t deflatedBound(ZlibStreams &z, size_t rawBytes);
// Both return false if zlib fails; inflateFrame also if the output is not
// exactly out.size() bytes.
bool deflateFrame(ZlibStreams &z, std::span<const uint8_t> in, std::span<uint8_t> out,
		  size_t *outSize);
bool inflateFrame(ZlibStreams &z, std::span<const uint8_t> in, std::span<uint8_t> out);

// Bytes of one raw frame.
inline size_t rawFrameBytes(const RecordingHeader &h)
{
	return static_cast<size_t>(h.intrinsics.width) * h.intrinsics.height * 2;
}

} // namespace ihf::recording
