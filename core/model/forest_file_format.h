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
inline constexpr uint32_t kNearSymmetryRecordSize = 32;
// Meshes of at most this many vertices store their faces as u16 x 3.
inline constexpr uint64_t kMaxShortFaceVertices = uint64_t{1} << 16;

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

// Element size of a TEMPLATES section: dims floats per template (float32),
// 1 (uint8: variable-length sparse records).
uint64_t templateBytes(uint64_t dims, TemplateEncoding encoding);

// Checks a tree's sparse 8-bit templates: record k starts at offsets[k], the
// first at 0 and each next where the previous ends (bitmap plus one value per
// set bit), the last ending at size; no bit set past dims. Adds the stored
// values to bins. Returns what is wrong, starting with "template K: ".
std::optional<std::string> checkSparseTemplates(const uint8_t *data, uint64_t size,
						std::span<const uint32_t> offsets, int dims,
						uint64_t &bins);

// One NEAR_SYMMETRIES record (forest_file.h) written and read.
void encodeNearSymmetry(const NearSymmetry &s, std::byte *out);
NearSymmetry decodeNearSymmetry(const std::byte *in);
// What is wrong with a near-symmetry (an axis not of unit length, a turn
// outside [0, 360), a share outside [0, 1], a number not finite), if
// anything.
std::optional<std::string> checkNearSymmetry(const NearSymmetry &s);

// Checks that every vote's rotation index is below rotationCount; returns
// what is wrong, starting with "vote V: ".
std::optional<std::string> checkVoteRotations(std::span<const PackedVote> votes,
					      uint64_t rotationCount);

// Checks one tree against the rules in forest_file.h and fills its
// statistics (templates is set to templateCount). Returns what is wrong,
// starting with "node N: " where a node is at fault, to follow "tree T ".
std::optional<std::string> checkTree(std::span<const TreeNode> nodes, uint64_t templateCount,
				     uint64_t voteCount, ForestTreeStats &stats);

} // namespace ihf::forestfile
