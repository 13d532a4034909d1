// SPDX-License-Identifier: MIT
// saveModelFile(): lays out the sections, checks the forest with the
// loader's rules, and writes header, table and sections atomically.

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <limits>
#include <system_error>
#include <vector>

#include "core/dataset/atomic_file.h"
#include "core/features/hocp.h"
#include "core/model/forest_file.h"
#include "core/model/forest_file_format.h"
#include "core/model/model_params_json.h"

namespace ihf {

namespace fs = std::filesystem;
using namespace forestfile;

namespace {

struct OutSection {
	ForestFileSection entry;
	const void *data = nullptr;
};

Error fault(const fs::path &path, const std::string &what)
{
	return makeError(Errc::kInvalidArgument, path.string() + ": cannot save: " + what);
}

} // namespace

Status saveModelFile(const fs::path &path, const ModelParams &params, const Mesh &mesh,
		     const ForestView &forest, std::span<const NearSymmetry> nearSymmetries)
{
	if constexpr (!kHostLittleEndian)
		return makeError(Errc::kUnsupported,
				 path.string() + ": forest files are little-endian; this host is not");

	constexpr uint64_t kMaxCount = std::numeric_limits<uint32_t>::max();

	// PARAMS must read back, or the file would not load.
	Expected<std::string> json = modelParamsToJson(params);
	if (!json)
		return fault(path, json.error().message);
	Expected<ModelParams> reread = modelParamsFromJson(*json, "model parameters");
	if (!reread)
		return fault(path, reread.error().message);

	const int expectDims = hocpDimension(params.hocp);
	if (forest.dims <= 0 || forest.dims != expectDims)
		return fault(path, "forest dims " + std::to_string(forest.dims) +
					   " do not match the HoCP dimension " +
					   std::to_string(expectDims) + " of the parameters");
	if (forest.encoding != TemplateEncoding::kFloat32 &&
	    forest.encoding != TemplateEncoding::kUint8)
		return fault(path, "unknown template encoding " +
					   std::to_string(static_cast<uint32_t>(forest.encoding)));
	if (forest.trees.empty())
		return fault(path, "the forest has no trees");
	if (forest.trees.size() > kMaxCount)
		return fault(path, "too many trees");

	if (mesh.vertices.size() > kMaxCount || mesh.faces.size() > kMaxCount)
		return fault(path, "mesh too large for the format");
	if (!mesh.normals.empty() && mesh.normals.size() != mesh.vertices.size())
		return fault(path, "mesh has " + std::to_string(mesh.normals.size()) + " normals for " +
					   std::to_string(mesh.vertices.size()) + " vertices");
	for (size_t f = 0; f < mesh.faces.size(); ++f)
		for (uint32_t v : mesh.faces[f])
			if (v >= mesh.vertices.size())
				return fault(path, "mesh face " + std::to_string(f) + " uses vertex " +
							   std::to_string(v) + " of " +
							   std::to_string(mesh.vertices.size()));

	// The in-memory layout of the payload types is the file's.
	static_assert(sizeof(Eigen::Vector3f) == 12);
	static_assert(sizeof(std::array<uint32_t, 3>) == 12);

	std::array<std::byte, kForestRecordSize> forestRecord{};
	putU32(forestRecord.data() + 0, static_cast<uint32_t>(forest.dims));
	putU32(forestRecord.data() + 4, static_cast<uint32_t>(forest.encoding));
	putU32(forestRecord.data() + 8, static_cast<uint32_t>(forest.trees.size()));

	std::vector<OutSection> out;
	auto add = [&out](SectionType type, uint32_t tree, const void *data, uint64_t elementSize,
			  uint64_t count) {
		OutSection s;
		s.entry.type = type;
		s.entry.tree = tree;
		s.entry.size = elementSize * count;
		s.entry.elementSize = static_cast<uint32_t>(elementSize);
		s.entry.elementCount = static_cast<uint32_t>(count);
		s.data = data;
		out.push_back(s);
	};
	if (json->size() > kMaxCount)
		return fault(path, "parameters too large");
	add(SectionType::kParams, 0, json->data(), 1, json->size());
	add(SectionType::kForest, 0, forestRecord.data(), kForestRecordSize, 1);
	add(SectionType::kMeshVertices, 0, mesh.vertices.data(), 12, mesh.vertices.size());
	std::vector<uint16_t> shortFaces;
	if (mesh.vertices.size() <= kMaxShortFaceVertices) {
		shortFaces.reserve(3 * mesh.faces.size());
		for (const auto &face : mesh.faces)
			for (uint32_t v : face)
				shortFaces.push_back(static_cast<uint16_t>(v));
		add(SectionType::kMeshFaces, 0, shortFaces.data(), 6, mesh.faces.size());
	} else {
		add(SectionType::kMeshFaces, 0, mesh.faces.data(), 12, mesh.faces.size());
	}
	if (!mesh.normals.empty())
		add(SectionType::kMeshNormals, 0, mesh.normals.data(), 12, mesh.normals.size());
	if (forest.rotations.size() > kMaxForestRotations)
		return fault(path, std::to_string(forest.rotations.size()) +
					   " distinct vote rotations, a vote indexes at most " +
					   std::to_string(kMaxForestRotations));
	add(SectionType::kRotations, 0, forest.rotations.data(), sizeof(PackedRotation),
	    forest.rotations.size());
	if (nearSymmetries.size() > kMaxNearSymmetries)
		return fault(path, std::to_string(nearSymmetries.size()) + " near-symmetries, at most " +
					   std::to_string(kMaxNearSymmetries));
	std::vector<std::byte> symmetryRecords(kNearSymmetryRecordSize * nearSymmetries.size());
	for (size_t i = 0; i < nearSymmetries.size(); ++i) {
		if (auto bad = checkNearSymmetry(nearSymmetries[i]))
			return fault(path, "near-symmetry " + std::to_string(i) + ": " + *bad);
		encodeNearSymmetry(nearSymmetries[i], symmetryRecords.data() + kNearSymmetryRecordSize * i);
	}
	if (!nearSymmetries.empty())
		add(SectionType::kNearSymmetries, 0, symmetryRecords.data(), kNearSymmetryRecordSize,
		    nearSymmetries.size());

	const uint64_t perTemplate = templateBytes(forest.dims, forest.encoding);
	if (perTemplate > kMaxCount)
		return fault(path, "descriptor dimension too large");
	for (size_t t = 0; t < forest.trees.size(); ++t) {
		const TreeView &tree = forest.trees[t];
		const std::string at = "tree " + std::to_string(t) + ": ";
		if (tree.nodes.size() > kMaxCount || tree.votes.size() > kMaxCount)
			return fault(path, at + "too many nodes or votes");
		const bool sparse = forest.encoding == TemplateEncoding::kUint8;
		// A dense view carries no template count: the splits tell how many
		// exist. A sparse one has an offset per template.
		uint64_t templates = 0;
		for (const TreeNode &node : tree.nodes)
			if (!node.isLeaf())
				templates = std::max<uint64_t>(templates, uint64_t{node.templateIndex} + 1);
		uint64_t templateSize = templates * perTemplate;
		if ((templates > 0 || !tree.templateOffsets.empty()) && !tree.templates)
			return fault(path, at + "no template data");
		if (sparse) {
			if (tree.templateOffsets.size() < templates)
				return fault(path, at + std::to_string(tree.templateOffsets.size()) +
							   " template offsets for " +
							   std::to_string(templates) + " templates");
			templates = tree.templateOffsets.size();
			// The records' length follows from their bitmaps: walk them.
			templateSize = 0;
			for (uint32_t offset : tree.templateOffsets) {
				if (offset != templateSize)
					return fault(path, at + "template records are not back to back");
				uint64_t present = 0;
				const auto *bits = static_cast<const uint8_t *>(tree.templates) + offset;
				for (size_t b = 0; b < templateBitmapBytes(forest.dims); ++b)
					present += static_cast<uint64_t>(std::popcount(bits[b]));
				templateSize += templateBitmapBytes(forest.dims) + present;
			}
			if (templateSize > kMaxCount)
				return fault(path, at + "templates too large for the format");
			uint64_t bins = 0;
			if (auto bad = checkSparseTemplates(static_cast<const uint8_t *>(tree.templates),
							    templateSize, tree.templateOffsets,
							    forest.dims, bins))
				return fault(path, at + *bad);
		}
		if (auto bad = checkVoteRotations(tree.votes, forest.rotations.size()))
			return fault(path, at + *bad);
		ForestTreeStats stats;
		if (auto bad = checkTree(tree.nodes, templates, tree.votes.size(), stats))
			return fault(path, "tree " + std::to_string(t) + " " + *bad);
		const uint32_t tree32 = static_cast<uint32_t>(t);
		add(SectionType::kNodes, tree32, tree.nodes.data(), sizeof(TreeNode), tree.nodes.size());
		add(SectionType::kTemplates, tree32, tree.templates, sparse ? 1 : perTemplate,
		    sparse ? templateSize : templates);
		if (sparse)
			add(SectionType::kTemplateOffsets, tree32, tree.templateOffsets.data(),
			    sizeof(uint32_t), tree.templateOffsets.size());
		add(SectionType::kVotes, tree32, tree.votes.data(), sizeof(PackedVote),
		    tree.votes.size());
	}

	// Layout: header, table, then each section on a 64-byte boundary.
	uint64_t cursor = kHeaderSize + uint64_t{kEntrySize} * out.size();
	for (OutSection &s : out) {
		s.entry.offset = alignUp(cursor);
		s.entry.crc = crc32Of(s.data, s.entry.size);
		cursor = s.entry.offset + s.entry.size;
	}
	const uint64_t fileSize = alignUp(cursor);

	std::vector<std::byte> table(uint64_t{kEntrySize} * out.size());
	for (size_t i = 0; i < out.size(); ++i)
		encodeEntry(out[i].entry, table.data() + i * kEntrySize);

	std::array<std::byte, kHeaderSize> header{};
	std::memcpy(header.data(), kMagic, sizeof(kMagic));
	// The oldest version that holds the file: without near-symmetries a
	// version 2 reader reads it too.
	putU32(header.data() + kOffVersion, nearSymmetries.empty() ? kOldestForestFileVersion : kForestFileVersion);
	putU32(header.data() + kOffEndian, kEndianMarker);
	putU32(header.data() + kOffHeaderSize, kHeaderSize);
	putU32(header.data() + kOffSectionCount, static_cast<uint32_t>(out.size()));
	putU64(header.data() + kOffFileSize, fileSize);
	putU32(header.data() + kOffTableCrc, crc32Of(table.data(), table.size()));
	putU32(header.data() + kOffEntrySize, kEntrySize);
	putU32(header.data() + kOffHeaderCrc, crc32Of(header.data(), header.size()));

	// No folder is created: a wrong output path should fail, not scatter files.
	const fs::path parent = path.parent_path();
	std::error_code ec;
	if (!parent.empty() && !fs::is_directory(parent, ec))
		return makeError(Errc::kNotFound,
				 path.string() + ": cannot save: folder " + parent.string() +
					 " does not exist");

	return writeFileAtomic(path, [&](std::FILE *stream) -> Status {
		static constexpr std::array<std::byte, kAlignment> kZeros{};
		uint64_t written = 0;
		auto write = [&](const void *data, uint64_t size) {
			if (size > 0 && std::fwrite(data, 1, size, stream) != size)
				return false;
			written += size;
			return true;
		};
		auto padTo = [&](uint64_t offset) { return write(kZeros.data(), offset - written); };
		bool ok = write(header.data(), header.size()) && write(table.data(), table.size());
		for (const OutSection &s : out)
			ok = ok && padTo(s.entry.offset) && write(s.data, s.entry.size);
		ok = ok && padTo(fileSize);
		if (!ok)
			return makeError(Errc::kIo, path.string() + ": write failed: " +
						    std::error_code(errno, std::generic_category()).message());
		return {};
	});
}

} // namespace ihf
