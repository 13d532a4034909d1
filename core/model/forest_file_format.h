// SPDX-License-Identifier: MIT
#pragma once

// Internal to the forest file reader and writer: the byte layout of the
// header and section table (see forest_file.h), explicit little-endian field
// access, and the tree rules both sides enforce.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "core/forest/forest_view.h"
#include "core/model/forest_file.h"

namespace ihf::forestfile {

inline constexpr char kMagic[8] = {'I', 'H', 'F', 'O', 'R', 'E', 'S', 'T'};
inline constexpr uint32_t kEndianMarker = 0x01020304;
inline constexpr uint32_t kHeaderSize = 64;
inline constexpr uint32_t kEntrySize = 48;
inline constexpr uint64_t kAlignment = 64;
inline constexpr uint32_t kForestRecordSize = 32;

// Header field offsets.
inline constexpr size_t kOffVersion = 8;
inline constexpr size_t kOffEndian = 12;
inline constexpr size_t kOffHeaderSize = 16;
inline constexpr size_t kOffSectionCount = 20;
inline constexpr size_t kOffFileSize = 24;
inline constexpr size_t kOffHeaderCrc = 32;
inline constexpr size_t kOffTableCrc = 36;
inline constexpr size_t kOffEntrySize = 40;

// The payload (nodes, floats, votes) is used in place, so the host must
// share the file's byte order.
inline constexpr bool kHostLittleEndian = std::endian::native == std::endian::little;

inline uint64_t alignUp(uint64_t v)
{
	return (v + kAlignment - 1) / kAlignment * kAlignment;
}

inline void putU32(std::byte *p, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		p[i] = static_cast<std::byte>(v >> (8 * i));
}

inline void putU64(std::byte *p, uint64_t v)
{
	for (int i = 0; i < 8; ++i)
		p[i] = static_cast<std::byte>(v >> (8 * i));
}

inline uint32_t getU32(const std::byte *p)
{
	uint32_t v = 0;
	for (int i = 0; i < 4; ++i)
		v |= static_cast<uint32_t>(p[i]) << (8 * i);
	return v;
}

inline uint64_t getU64(const std::byte *p)
{
	uint64_t v = 0;
	for (int i = 0; i < 8; ++i)
		v |= static_cast<uint64_t>(p[i]) << (8 * i);
	return v;
}

uint32_t crc32Of(const void *data, uint64_t size);

void encodeEntry(const ForestFileSection &s, std::byte *out);
ForestFileSection decodeEntry(const std::byte *in);

// Bytes per template of a forest: dims entries of the encoding's size.
uint64_t templateBytes(uint64_t dims, TemplateEncoding encoding);

// Checks one tree against the rules in forest_file.h and fills its
// statistics (templates is set to templateCount). Returns what is wrong,
// starting with "node N: " where a node is at fault, to follow "tree T ".
std::optional<std::string> checkTree(std::span<const TreeNode> nodes, uint64_t templateCount,
				     uint64_t voteCount, ForestTreeStats &stats);

} // namespace ihf::forestfile
