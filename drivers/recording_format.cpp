// SPDX-License-Identifier: MIT
#include "drivers/recording_format.h"

#include <cmath>
#include <cstdio>

#include <zlib.h>

namespace ihf::recording {

namespace {

// Byte offsets of the header fields (docs/recording.md).
constexpr size_t kOffVersion = 8;
constexpr size_t kOffHeaderSize = 12;
constexpr size_t kOffWidth = 16;
constexpr size_t kOffHeight = 20;
constexpr size_t kOffFx = 24;
constexpr size_t kOffFy = 32;
constexpr size_t kOffCx = 40;
constexpr size_t kOffCy = 48;
constexpr size_t kOffDepthScale = 56;
constexpr size_t kOffSensorIdSize = 64;

Error fieldError(Errc code, const std::string &source, const char *field, const std::string &what)
{
	return makeError(code, source + ": recording header field '" + field + "': " + what);
}

std::string hexBytes(std::span<const uint8_t> bytes)
{
	std::string s;
	char buf[4];
	for (uint8_t b : bytes) {
		std::snprintf(buf, sizeof(buf), "%02x", b);
		s += buf;
	}
	return s;
}

} // namespace

uint32_t crc32Of(std::span<const uint8_t> bytes, uint32_t crc)
{
	// zlib's crc32 takes uInt lengths; feed large spans in pieces.
	uLong c = crc;
	size_t done = 0;
	while (done < bytes.size()) {
		const size_t n = std::min<size_t>(bytes.size() - done, 1u << 30);
		c = ::crc32(c, bytes.data() + done, static_cast<uInt>(n));
		done += n;
	}
	return static_cast<uint32_t>(c);
}

Expected<std::vector<uint8_t>> encodeHeader(const RecordingHeader &header)
{
	const CameraIntrinsics &k = header.intrinsics;
	if (k.width <= 0 || k.height <= 0 || k.width > kMaxDimension || k.height > kMaxDimension)
		return makeError(Errc::kInvalidArgument,
				 "recording header: frame size " + std::to_string(k.width) + "x" +
					 std::to_string(k.height) + " is out of range");
	if (header.sensorId.size() > kMaxSensorIdSize)
		return makeError(Errc::kInvalidArgument, "recording header: sensor id longer than " +
								 std::to_string(kMaxSensorIdSize) + " bytes");
	if (!(header.depthScale > 0) || !std::isfinite(header.depthScale))
		return makeError(Errc::kInvalidArgument, "recording header: depth scale must be > 0");

	const size_t size = kHeaderFixedSize + header.sensorId.size() + 4;
	std::vector<uint8_t> out(size, 0);
	std::copy(kFileMagic.begin(), kFileMagic.end(), out.begin());
	putU32(&out[kOffVersion], kVersion);
	putU32(&out[kOffHeaderSize], static_cast<uint32_t>(size));
	putU32(&out[kOffWidth], static_cast<uint32_t>(k.width));
	putU32(&out[kOffHeight], static_cast<uint32_t>(k.height));
	putF64(&out[kOffFx], k.fx);
	putF64(&out[kOffFy], k.fy);
	putF64(&out[kOffCx], k.cx);
	putF64(&out[kOffCy], k.cy);
	putF64(&out[kOffDepthScale], header.depthScale);
	putU32(&out[kOffSensorIdSize], static_cast<uint32_t>(header.sensorId.size()));
	std::memcpy(&out[kHeaderFixedSize], header.sensorId.data(), header.sensorId.size());
	putU32(&out[size - 4], crc32Of(std::span(out).first(size - 4)));
	return out;
}

Expected<RecordingHeader> decodeHeader(std::span<const uint8_t> bytes, const std::string &source,
				       size_t *headerSize)
{
	auto truncated = [&](const char *field, size_t need) {
		return fieldError(Errc::kCorrupt, source, field,
				  "file ends inside the header (" + std::to_string(bytes.size()) +
					  " bytes, the field needs " + std::to_string(need) + ")");
	};

	if (bytes.size() < kFileMagic.size())
		return truncated("magic", kFileMagic.size());
	if (!std::equal(kFileMagic.begin(), kFileMagic.end(), bytes.begin()))
		return fieldError(Errc::kParse, source, "magic",
				  "not an ihf recording (expected bytes " + hexBytes(kFileMagic) +
					  ", found " + hexBytes(bytes.first(kFileMagic.size())) + ")");
	if (bytes.size() < kOffVersion + 4)
		return truncated("version", kOffVersion + 4);
	RecordingHeader h;
	h.version = getU32(&bytes[kOffVersion]);
	if (h.version != kVersion)
		return fieldError(Errc::kUnsupported, source, "version",
				  "version " + std::to_string(h.version) + " is not supported (this build reads version " +
					  std::to_string(kVersion) + ")");
	if (bytes.size() < kHeaderFixedSize)
		return truncated("sensor_id_size", kHeaderFixedSize);

	const uint32_t idSize = getU32(&bytes[kOffSensorIdSize]);
	if (idSize > kMaxSensorIdSize)
		return fieldError(Errc::kCorrupt, source, "sensor_id_size",
				  std::to_string(idSize) + " bytes exceeds the limit of " +
					  std::to_string(kMaxSensorIdSize));
	const size_t size = kHeaderFixedSize + idSize + 4;
	const uint32_t declared = getU32(&bytes[kOffHeaderSize]);
	if (declared != size)
		return fieldError(Errc::kCorrupt, source, "header_size",
				  "says " + std::to_string(declared) + " bytes, the fields take " +
					  std::to_string(size));
	if (bytes.size() < size)
		return truncated("header_crc", size);
	const uint32_t crc = getU32(&bytes[size - 4]);
	const uint32_t actual = crc32Of(bytes.first(size - 4));
	if (crc != actual) {
		char buf[64];
		std::snprintf(buf, sizeof(buf), "stored %08x, computed %08x", crc, actual);
		return fieldError(Errc::kCorrupt, source, "header_crc", buf);
	}

	const uint32_t w = getU32(&bytes[kOffWidth]);
	const uint32_t hgt = getU32(&bytes[kOffHeight]);
	if (w == 0 || w > kMaxDimension)
		return fieldError(Errc::kCorrupt, source, "width", std::to_string(w) + " is out of range");
	if (hgt == 0 || hgt > kMaxDimension)
		return fieldError(Errc::kCorrupt, source, "height", std::to_string(hgt) + " is out of range");
	h.intrinsics.width = static_cast<int>(w);
	h.intrinsics.height = static_cast<int>(hgt);
	h.intrinsics.fx = getF64(&bytes[kOffFx]);
	h.intrinsics.fy = getF64(&bytes[kOffFy]);
	h.intrinsics.cx = getF64(&bytes[kOffCx]);
	h.intrinsics.cy = getF64(&bytes[kOffCy]);
	h.depthScale = getF64(&bytes[kOffDepthScale]);
	for (auto [name, v] : {std::pair{"fx", h.intrinsics.fx}, std::pair{"fy", h.intrinsics.fy},
			       std::pair{"cx", h.intrinsics.cx}, std::pair{"cy", h.intrinsics.cy}})
		if (!std::isfinite(v))
			return fieldError(Errc::kCorrupt, source, name, "is not a finite number");
	if (!(h.depthScale > 0) || !std::isfinite(h.depthScale))
		return fieldError(Errc::kCorrupt, source, "depth_scale", "must be a positive number");
	h.sensorId.assign(reinterpret_cast<const char *>(&bytes[kHeaderFixedSize]), idSize);
	*headerSize = size;
	return h;
}

void encodeFrameRecord(const FrameRecord &r, uint8_t *out)
{
	putU32(out, kFrameMagic);
	putU32(out + 4, static_cast<uint32_t>(r.encoding));
	putU64(out + 8, r.index);
	putU64(out + 16, static_cast<uint64_t>(r.deviceTimestampNs));
	putU64(out + 24, static_cast<uint64_t>(r.hostTimestampNs));
	putU32(out + 32, r.payloadSize);
	putU32(out + kFrameCrcOffset, r.crc);
}

FrameRecord decodeFrameRecord(const uint8_t *in)
{
	FrameRecord r;
	r.encoding = static_cast<Encoding>(getU32(in + 4));
	r.index = getU64(in + 8);
	r.deviceTimestampNs = static_cast<int64_t>(getU64(in + 16));
	r.hostTimestampNs = static_cast<int64_t>(getU64(in + 24));
	r.payloadSize = getU32(in + 32);
	r.crc = getU32(in + kFrameCrcOffset);
	return r;
}

uint32_t frameCrc(const uint8_t *recordHeader, std::span<const uint8_t> payload)
{
	return crc32Of(payload, crc32Of(std::span(recordHeader, kFrameCrcOffset)));
}

struct ZlibStreams {
	z_stream stream{};
	bool deflating = false;
};

void ZlibStreamsDeleter::operator()(ZlibStreams *z) const
{
	if (z->deflating)
		deflateEnd(&z->stream);
	else
		inflateEnd(&z->stream);
	delete z;
}

ZlibStreamsPtr makeInflater()
{
	ZlibStreamsPtr z(new ZlibStreams);
	if (inflateInit(&z->stream) != Z_OK) {
		delete z.release(); // nothing to end
		return nullptr;
	}
	return z;
}

ZlibStreamsPtr makeDeflater(int level)
{
	ZlibStreamsPtr z(new ZlibStreams);
	z->deflating = true;
	if (deflateInit(&z->stream, level) != Z_OK) {
		delete z.release();
		return nullptr;
	}
	return z;
}

size_t deflatedBound(ZlibStreams &z, size_t rawBytes)
{
	return deflateBound(&z.stream, static_cast<uLong>(rawBytes));
}

bool deflateFrame(ZlibStreams &z, std::span<const uint8_t> in, std::span<uint8_t> out,
		  size_t *outSize)
{
	if (deflateReset(&z.stream) != Z_OK)
		return false;
	z.stream.next_in = const_cast<Bytef *>(in.data());
	z.stream.avail_in = static_cast<uInt>(in.size());
	z.stream.next_out = out.data();
	z.stream.avail_out = static_cast<uInt>(out.size());
	if (deflate(&z.stream, Z_FINISH) != Z_STREAM_END)
		return false;
	*outSize = out.size() - z.stream.avail_out;
	return true;
}

bool inflateFrame(ZlibStreams &z, std::span<const uint8_t> in, std::span<uint8_t> out)
{
	if (inflateReset(&z.stream) != Z_OK)
		return false;
	z.stream.next_in = const_cast<Bytef *>(in.data());
	z.stream.avail_in = static_cast<uInt>(in.size());
	z.stream.next_out = out.data();
	z.stream.avail_out = static_cast<uInt>(out.size());
	return inflate(&z.stream, Z_FINISH) == Z_STREAM_END && z.stream.avail_out == 0;
}

} // namespace ihf::recording
