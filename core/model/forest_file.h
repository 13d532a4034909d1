// SPDX-License-Identifier: MIT
#pragma once

// The forest file (.ihf): one trained object (parameters, mesh, Hough
// forest) in a versioned, checksummed container that inference maps and uses
// in place. All integers and floats are little-endian.
//
// Layout, version 3 (version 2 is the same without NEAR_SYMMETRIES; both load):
//   header, 64 bytes:
//     0  char[8] magic "IHFOREST"
//     8  u32 version (2, or 3 with NEAR_SYMMETRIES)
//     12 u32 endianness marker 0x01020304 (bytes 04 03 02 01)
//     16 u32 header size (64)
//     20 u32 section count
//     24 u64 file size
//     32 u32 CRC32 of the 64 header bytes with this field zeroed
//     36 u32 CRC32 of the section table
//     40 u32 section table entry size (48)
//     44 reserved, zero
//   section table at offset 64, one 48-byte entry per section:
//     0  u32 type (SectionType)      4  u32 tree index (0 for non-tree sections)
//     8  u64 offset                  16 u64 size in bytes
//     24 u32 element size            28 u32 element count (size = element size * count)
//     32 u32 CRC32 of the section bytes (zlib crc32)
//     36 reserved, zero
//   sections, each on a 64-byte boundary, zero padding between them:
//     PARAMS         ModelParams as JSON text (model_params_json.h), element size 1
//     FOREST         one 32-byte record {u32 dims, u32 encoding, u32 tree count, reserved}
//     MESH_VERTICES  float32 x, y, z per vertex (mm)
//     MESH_FACES     uint16 x 3 per face when the mesh has at most 65536
//                    vertices, else uint32 x 3
//     MESH_NORMALS   float32 x 3 per vertex (optional; inference reads none,
//                    so ihf train leaves them out)
//     ROTATIONS      the forest's distinct vote rotations (PackedRotation,
//                    int16 x, y, z, w * 32767; at most 65536)
//     NEAR_SYMMETRIES (optional, version 3) the object's near-symmetries
//                    (near_symmetry.h), 32 bytes each: float32 axis[3] (unit),
//                    point[3] (mm), turn (deg, 0: continuous, else in (0, 360)),
//                    differing share (in [0, 1]); at most kMaxNearSymmetries
//     per tree t:  NODES (TreeNode, 32 bytes),
//                  TEMPLATES float32 encoding: one element of dims float32
//                            per split template; uint8 encoding: element
//                            size 1, the sparse records (forest_view.h) of
//                            the templates back to back,
//                  TEMPLATE_OFFSETS (uint8 encoding only) u32 byte offset of
//                            each template's record in TEMPLATES,
//                  VOTES (PackedVote, 8 bytes: int16 offset[3] mm, u16
//                         rotation index)
//
// Loading validates everything once (header, CRCs, bounds, every node: a
// leaf has both children -1, a split has both children after itself and
// inside the tree, its template exists, a leaf's votes lie inside the tree's
// votes; every sparse record inside TEMPLATES and the next one starting where
// it ends; every vote's rotation inside ROTATIONS; depth <= kMaxTreeDepth;
// face indices; dims == hocpDimension), so a tree walk needs no checks and
// visits at most kMaxTreeDepth nodes. Big-endian hosts are refused (the
// payload is used in place). Files of another version than 2 or 3 are
// refused with a message naming the versions.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "core/model/object_model.h"

namespace ihf {

inline constexpr uint32_t kForestFileVersion = 3;
inline constexpr uint32_t kOldestForestFileVersion = 2; // still read
inline constexpr uint32_t kMaxNearSymmetries = 16;
inline constexpr int kMaxTreeDepth = 64; // nodes on the longest root-to-leaf path

enum class SectionType : uint32_t {
	kParams = 1,
	kForest = 2,
	kMeshVertices = 3,
	kMeshFaces = 4,
	kMeshNormals = 5,
	kRotations = 6,
	kNearSymmetries = 7,
	kNodes = 16,
	kTemplates = 17,
	kVotes = 18,
	kTemplateOffsets = 19,
};

// "PARAMS", "NODES", ...; "UNKNOWN" for other values.
const char *sectionTypeName(SectionType type);

struct ForestFileSection {
	SectionType type = SectionType::kParams;
	uint32_t tree = 0;
	uint64_t offset = 0;
	uint64_t size = 0;
	uint32_t elementSize = 0;
	uint32_t elementCount = 0;
	uint32_t crc = 0;
};

struct ForestTreeStats {
	uint32_t nodes = 0;
	uint32_t leaves = 0;
	uint32_t templates = 0;
	uint32_t votes = 0;
	uint64_t templateBins = 0; // stored template values (uint8: the non-zero bins)
	int depth = 0; // nodes on the longest root-to-leaf path
};

// What `ihf forest info` prints; filled by a successful, validated load.
struct ForestFileSummary {
	std::filesystem::path path;
	uint32_t version = 0;
	uint64_t fileSize = 0;
	uint32_t headerCrc = 0;
	uint32_t tableCrc = 0;
	std::vector<ForestFileSection> sections;
	int dims = 0;
	TemplateEncoding encoding = TemplateEncoding::kFloat32;
	std::vector<ForestTreeStats> trees;
	size_t vertices = 0;
	size_t faces = 0;
	bool normals = false;
	uint32_t rotations = 0;
	std::vector<NearSymmetry> nearSymmetries;
	ModelParams params;
	std::string paramsJson; // the PARAMS section as stored
};

// A model loaded from a forest file: the forest view points into the
// read-only private mapping, which lives as long as this object.
class MappedObjectModel : public ObjectModel
{
public:
	~MappedObjectModel() override;
	MappedObjectModel(const MappedObjectModel &) = delete;
	MappedObjectModel &operator=(const MappedObjectModel &) = delete;

	const ModelParams &params() const override { return summary_.params; }
	const Mesh &mesh() const override { return mesh_; }
	const ForestView &forest() const override { return view_; }
	std::span<const NearSymmetry> nearSymmetries() const override { return summary_.nearSymmetries; }

	const ForestFileSummary &summary() const { return summary_; }
	// The mapped file bytes.
	std::span<const std::byte> mapping() const { return {mapping_, mappingSize_}; }

private:
	friend Expected<std::unique_ptr<ObjectModel>> loadModelFile(const std::filesystem::path &path);
	MappedObjectModel() = default;

	const std::byte *mapping_ = nullptr;
	size_t mappingSize_ = 0;
	ForestFileSummary summary_;
	Mesh mesh_;
	std::vector<TreeView> trees_;
	ForestView view_;
};

// Writes the file atomically (temporary file in the same folder, renamed into
// place; nothing is left behind on failure), as version 2 when there are no
// near-symmetries (version 2 readers read it too), else version 3. The folder must exist. The
// forest is checked with the same rules the loader applies, so a file that
// saves also loads. A tree's template count is one past the largest
// templateIndex of its split nodes.
// nearSymmetries: at most kMaxNearSymmetries, each valid (near_symmetry.h).
Status saveModelFile(const std::filesystem::path &path, const ModelParams &params, const Mesh &mesh,
		     const ForestView &forest, std::span<const NearSymmetry> nearSymmetries = {});

// Maps and validates the file; on any failure an Error naming the file and
// the fault, and nothing stays mapped. The result is a MappedObjectModel.
Expected<std::unique_ptr<ObjectModel>> loadModelFile(const std::filesystem::path &path);

// Loads (fully validated) and returns the summary.
Expected<ForestFileSummary> summariseModelFile(const std::filesystem::path &path);

// Human-readable summary: header, section table, bytes by part of the model
// (mesh, nodes, templates, votes, the rest), forest and per-tree statistics,
// mesh, near-symmetries, parameters.
std::string formatForestFileSummary(const ForestFileSummary &summary);

} // namespace ihf
