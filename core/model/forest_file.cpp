// SPDX-License-Identifier: MIT
// loadModelFile(): maps a forest file and validates all of it once, so the
// forest view can point straight into the mapping and a tree walk needs no
// checks.

#include "core/model/forest_file.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/common/errno_text.h"
#include "core/features/hocp.h"
#include "core/model/forest_file_format.h"
#include "core/model/model_params_json.h"

namespace ihf {

namespace fs = std::filesystem;
using namespace forestfile;

namespace {

std::string hex32(uint32_t v)
{
	char buf[16];
	std::snprintf(buf, sizeof(buf), "0x%08x", v);
	return buf;
}

std::string describe(const ForestFileSection &s)
{
	std::string d = sectionTypeName(s.type);
	switch (s.type) {
	case SectionType::kNodes:
	case SectionType::kTemplates:
	case SectionType::kTemplateOffsets:
	case SectionType::kVotes:
		d += " of tree " + std::to_string(s.tree);
		break;
	default:
		break;
	}
	return d;
}

bool isTreeSection(SectionType t)
{
	return t == SectionType::kNodes || t == SectionType::kTemplates ||
	       t == SectionType::kTemplateOffsets || t == SectionType::kVotes;
}

bool isKnown(SectionType t)
{
	return std::strcmp(sectionTypeName(t), "UNKNOWN") != 0;
}

void readVectors(const std::byte *p, size_t count, std::vector<Eigen::Vector3f> &out)
{
	out.resize(count);
	for (size_t i = 0; i < count; ++i) {
		float v[3];
		std::memcpy(v, p + 12 * i, sizeof(v));
		out[i] = Eigen::Vector3f(v[0], v[1], v[2]);
	}
}

// Closes the descriptor on every path out of the loader.
class FdGuard
{
public:
	explicit FdGuard(int fd) : fd_(fd) {}
	~FdGuard()
	{
		if (fd_ >= 0)
			::close(fd_);
	}
	FdGuard(const FdGuard &) = delete;
	FdGuard &operator=(const FdGuard &) = delete;
	int get() const { return fd_; }

private:
	int fd_;
};

} // namespace

MappedObjectModel::~MappedObjectModel()
{
	if (mapping_)
		::munmap(const_cast<std::byte *>(mapping_), mappingSize_);
}

Expected<std::unique_ptr<ObjectModel>> loadModelFile(const fs::path &path)
{
	const std::string name = path.string();
	auto corrupt = [&name](const std::string &what) {
		return makeError(Errc::kCorrupt, name + ": " + what);
	};

	if constexpr (!kHostLittleEndian)
		return makeError(Errc::kUnsupported,
				 name + ": forest files are little-endian and used in place; "
					"this big-endian host cannot load them");

	FdGuard fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
	if (fd.get() < 0) {
		int err = errno;
		if (err == ENOENT)
			return makeError(Errc::kNotFound, name + ": file not found");
		return makeError(Errc::kIo, name + ": cannot open: " + errnoText(err));
	}
	struct stat st;
	if (::fstat(fd.get(), &st) != 0)
		return makeError(Errc::kIo, name + ": cannot stat: " + errnoText(errno));
	if (!S_ISREG(st.st_mode))
		return makeError(Errc::kIo, name + ": not a regular file");
	const uint64_t actualSize = static_cast<uint64_t>(st.st_size);
	if (actualSize < kHeaderSize)
		return corrupt("truncated: " + std::to_string(actualSize) +
			       " bytes, smaller than the " + std::to_string(kHeaderSize) +
			       "-byte header");

	// 32-bit targets: size_t would truncate the length of the mapping.
	if constexpr (sizeof(size_t) < sizeof(uint64_t))
		if (actualSize > std::numeric_limits<size_t>::max())
			return makeError(Errc::kUnsupported,
					 name + ": too large to map on this 32-bit target");

	void *addr = ::mmap(nullptr, static_cast<size_t>(actualSize), PROT_READ, MAP_PRIVATE,
			    fd.get(), 0);
	if (addr == MAP_FAILED)
		return makeError(Errc::kIo, name + ": cannot map: " + errnoText(errno));

	// From here on the model owns the mapping: any error return unmaps it.
	std::unique_ptr<MappedObjectModel> model(new MappedObjectModel());
	model->mapping_ = static_cast<const std::byte *>(addr);
	model->mappingSize_ = actualSize;
	const std::byte *base = model->mapping_;
	ForestFileSummary &sum = model->summary_;
	sum.path = path;

	// Header.
	if (std::memcmp(base, kMagic, sizeof(kMagic)) != 0)
		return corrupt("not an ihf forest file (magic is not \"IHFOREST\")");
	const uint32_t marker = getU32(base + kOffEndian);
	if (marker == 0x04030201)
		return makeError(Errc::kUnsupported,
				 name + ": written big-endian; forest files must be little-endian");
	if (marker != kEndianMarker)
		return corrupt("bad endianness marker " + hex32(marker));
	sum.version = getU32(base + kOffVersion);
	if (sum.version < kOldestForestFileVersion || sum.version > kForestFileVersion)
		return makeError(Errc::kUnsupported,
				 name + ": forest file version " + std::to_string(sum.version) +
					 "; this ihf reads " + std::to_string(kOldestForestFileVersion) + " to " +
					 std::to_string(kForestFileVersion) + ": retrain with ihf train");
	if (getU32(base + kOffHeaderSize) != kHeaderSize)
		return corrupt("header size " + std::to_string(getU32(base + kOffHeaderSize)) +
			       ", the format has " + std::to_string(kHeaderSize));
	std::array<std::byte, kHeaderSize> header;
	std::memcpy(header.data(), base, kHeaderSize);
	sum.headerCrc = getU32(base + kOffHeaderCrc);
	putU32(header.data() + kOffHeaderCrc, 0);
	if (crc32Of(header.data(), header.size()) != sum.headerCrc)
		return corrupt("header CRC mismatch");
	sum.fileSize = getU64(base + kOffFileSize);
	if (actualSize < sum.fileSize)
		return corrupt("truncated: the header says " + std::to_string(sum.fileSize) +
			       " bytes, the file has " + std::to_string(actualSize));
	if (actualSize > sum.fileSize)
		return corrupt(std::to_string(actualSize) + " bytes but the header says " +
			       std::to_string(sum.fileSize) + " (trailing data)");
	if (getU32(base + kOffEntrySize) != kEntrySize)
		return corrupt("section entry size " + std::to_string(getU32(base + kOffEntrySize)) +
			       ", the format has " + std::to_string(kEntrySize));
	const uint64_t sectionCount = getU32(base + kOffSectionCount);
	const uint64_t tableEnd = kHeaderSize + sectionCount * kEntrySize;
	if (tableEnd > sum.fileSize)
		return corrupt("section table (" + std::to_string(sectionCount) +
			       " entries) runs past the end of the file");
	sum.tableCrc = getU32(base + kOffTableCrc);
	if (crc32Of(base + kHeaderSize, tableEnd - kHeaderSize) != sum.tableCrc)
		return corrupt("section table CRC mismatch");

	// Sections: placement and checksums.
	for (uint64_t i = 0; i < sectionCount; ++i) {
		ForestFileSection s = decodeEntry(base + kHeaderSize + i * kEntrySize);
		const std::string at = "section " + std::to_string(i) + " (" + describe(s) + "): ";
		if (!isKnown(s.type))
			return corrupt(at + "unknown section type " +
				       std::to_string(static_cast<uint32_t>(s.type)));
		if (!isTreeSection(s.type) && s.tree != 0)
			return corrupt(at + "tree index " + std::to_string(s.tree) +
				       " on a section that belongs to no tree");
		if (s.offset % kAlignment != 0)
			return corrupt(at + "offset " + std::to_string(s.offset) +
				       " not on a 64-byte boundary");
		if (s.offset < tableEnd || s.offset > sum.fileSize || s.size > sum.fileSize - s.offset)
			return corrupt(at + "bytes [" + std::to_string(s.offset) + ", +" +
				       std::to_string(s.size) + ") outside the data area of the file");
		if (s.size != uint64_t{s.elementSize} * s.elementCount)
			return corrupt(at + "size " + std::to_string(s.size) + " is not " +
				       std::to_string(s.elementCount) + " elements of " +
				       std::to_string(s.elementSize) + " bytes");
		if (crc32Of(base + s.offset, s.size) != s.crc)
			return corrupt(at + "CRC mismatch (" + describe(s) + " is damaged)");
		sum.sections.push_back(s);
	}
	{
		std::vector<ForestFileSection> byOffset = sum.sections;
		std::sort(byOffset.begin(), byOffset.end(),
			  [](const auto &a, const auto &b) { return a.offset < b.offset; });
		for (size_t i = 1; i < byOffset.size(); ++i)
			if (byOffset[i].offset < byOffset[i - 1].offset + byOffset[i - 1].size)
				return corrupt("sections " + describe(byOffset[i - 1]) + " and " +
					       describe(byOffset[i]) + " overlap");
	}

	// Which section is which; each exactly once.
	std::map<std::pair<SectionType, uint32_t>, const ForestFileSection *> found;
	for (const ForestFileSection &s : sum.sections)
		if (!found.emplace(std::make_pair(s.type, s.tree), &s).second)
			return corrupt("two " + describe(s) + " sections");
	auto section = [&found](SectionType type, uint32_t tree = 0) -> const ForestFileSection * {
		auto it = found.find({type, tree});
		return it == found.end() ? nullptr : it->second;
	};
	for (SectionType t : {SectionType::kParams, SectionType::kForest, SectionType::kMeshVertices,
			      SectionType::kMeshFaces, SectionType::kRotations})
		if (!section(t))
			return corrupt(std::string("no ") + sectionTypeName(t) + " section");
	auto expectElement = [&](const ForestFileSection &s, uint64_t size) -> std::optional<Error> {
		if (s.elementSize != size)
			return corrupt(describe(s) + ": element size " + std::to_string(s.elementSize) +
				       ", expected " + std::to_string(size));
		return std::nullopt;
	};

	// PARAMS and FOREST.
	const ForestFileSection &paramsSec = *section(SectionType::kParams);
	if (auto e = expectElement(paramsSec, 1))
		return *e;
	sum.paramsJson.assign(reinterpret_cast<const char *>(base + paramsSec.offset), paramsSec.size);
	Expected<ModelParams> params = modelParamsFromJson(sum.paramsJson, name + ": PARAMS");
	if (!params)
		return params.error();
	sum.params = std::move(*params);

	const ForestFileSection &forestSec = *section(SectionType::kForest);
	if (auto e = expectElement(forestSec, kForestRecordSize))
		return *e;
	if (forestSec.elementCount != 1)
		return corrupt("FOREST: " + std::to_string(forestSec.elementCount) +
			       " records, expected 1");
	const std::byte *rec = base + forestSec.offset;
	const uint32_t dims = getU32(rec + 0);
	const uint32_t encoding = getU32(rec + 4);
	const uint32_t treeCount = getU32(rec + 8);
	const int expectDims = hocpDimension(sum.params.hocp);
	if (dims == 0 || static_cast<int64_t>(dims) != expectDims)
		return corrupt("FOREST: dims " + std::to_string(dims) +
			       " do not match the HoCP dimension " + std::to_string(expectDims) +
			       " of PARAMS");
	if (encoding != static_cast<uint32_t>(TemplateEncoding::kFloat32) &&
	    encoding != static_cast<uint32_t>(TemplateEncoding::kUint8))
		return corrupt("FOREST: unknown template encoding " + std::to_string(encoding));
	if (treeCount == 0)
		return corrupt("FOREST: no trees");
	// Each tree has three sections: refuse a count the table cannot hold
	// before reserving anything for it.
	if (treeCount > sectionCount / 3)
		return corrupt("FOREST: " + std::to_string(treeCount) + " trees but the section table has " +
			       std::to_string(sectionCount) + " sections (3 per tree)");
	sum.dims = static_cast<int>(dims);
	sum.encoding = static_cast<TemplateEncoding>(encoding);

	// Mesh, copied out (Mesh holds vectors).
	const ForestFileSection &vertSec = *section(SectionType::kMeshVertices);
	const ForestFileSection &faceSec = *section(SectionType::kMeshFaces);
	const ForestFileSection *normSec = section(SectionType::kMeshNormals);
	if (auto e = expectElement(vertSec, 12))
		return *e;
	// Faces are u16 x 3 when every vertex index fits 16 bits, else u32 x 3.
	const bool shortFaces = vertSec.elementCount <= kMaxShortFaceVertices;
	if (auto e = expectElement(faceSec, shortFaces ? 6 : 12))
		return *e;
	if (normSec) {
		if (auto e = expectElement(*normSec, 12))
			return *e;
		if (normSec->elementCount != vertSec.elementCount)
			return corrupt("MESH_NORMALS: " + std::to_string(normSec->elementCount) +
				       " normals for " + std::to_string(vertSec.elementCount) +
				       " vertices");
	}
	Mesh &mesh = model->mesh_;
	readVectors(base + vertSec.offset, vertSec.elementCount, mesh.vertices);
	mesh.faces.resize(faceSec.elementCount);
	if (shortFaces) {
		for (size_t f = 0; f < mesh.faces.size(); ++f)
			for (size_t k = 0; k < 3; ++k) {
				uint16_t v;
				std::memcpy(&v, base + faceSec.offset + 6 * f + 2 * k, sizeof(v));
				mesh.faces[f][k] = v;
			}
	} else {
		std::memcpy(mesh.faces.data(), base + faceSec.offset, faceSec.size);
	}
	for (size_t f = 0; f < mesh.faces.size(); ++f)
		for (uint32_t v : mesh.faces[f])
			if (v >= mesh.vertices.size())
				return corrupt("MESH_FACES: face " + std::to_string(f) + " uses vertex " +
					       std::to_string(v) + " of " +
					       std::to_string(mesh.vertices.size()));
	if (normSec) {
		readVectors(base + normSec->offset, normSec->elementCount, mesh.normals);
	}
	const ForestFileSection &rotSec = *section(SectionType::kRotations);
	if (auto e = expectElement(rotSec, sizeof(PackedRotation)))
		return *e;
	if (rotSec.elementCount > kMaxForestRotations)
		return corrupt("ROTATIONS: " + std::to_string(rotSec.elementCount) +
			       " rotations, a vote indexes at most " +
			       std::to_string(kMaxForestRotations));
	sum.rotations = rotSec.elementCount;
	if (const ForestFileSection *symSec = section(SectionType::kNearSymmetries)) {
		if (sum.version < 3)
			return corrupt("NEAR_SYMMETRIES in a version " + std::to_string(sum.version) + " file");
		if (auto e = expectElement(*symSec, kNearSymmetryRecordSize))
			return *e;
		if (symSec->elementCount > kMaxNearSymmetries)
			return corrupt("NEAR_SYMMETRIES: " + std::to_string(symSec->elementCount) + " records, at most " +
				       std::to_string(kMaxNearSymmetries));
		for (uint32_t i = 0; i < symSec->elementCount; ++i) {
			const NearSymmetry ns = decodeNearSymmetry(base + symSec->offset + kNearSymmetryRecordSize * i);
			if (auto bad = checkNearSymmetry(ns))
				return corrupt("NEAR_SYMMETRIES: record " + std::to_string(i) + ": " + *bad);
			sum.nearSymmetries.push_back(ns);
		}
	}
	sum.vertices = mesh.vertices.size();
	sum.faces = mesh.faces.size();
	sum.normals = normSec != nullptr;

	// Trees: every section present, every node checked; the views point
	// into the mapping.
	for (const ForestFileSection &s : sum.sections)
		if (isTreeSection(s.type) && s.tree >= treeCount)
			return corrupt(describe(s) + ": the forest has only " +
				       std::to_string(treeCount) + " trees");
	const uint64_t perTemplate = templateBytes(dims, sum.encoding);
	model->trees_.reserve(treeCount);
	for (uint32_t t = 0; t < treeCount; ++t) {
		const ForestFileSection *nodes = section(SectionType::kNodes, t);
		const ForestFileSection *templ = section(SectionType::kTemplates, t);
		const ForestFileSection *offsets = section(SectionType::kTemplateOffsets, t);
		const ForestFileSection *votes = section(SectionType::kVotes, t);
		for (auto [sec, type] : {std::pair{nodes, SectionType::kNodes},
					 std::pair{templ, SectionType::kTemplates},
					 std::pair{votes, SectionType::kVotes}})
			if (!sec)
				return corrupt(std::string("no ") + sectionTypeName(type) +
					       " section for tree " + std::to_string(t));
		const bool sparse = sum.encoding == TemplateEncoding::kUint8;
		if (sparse && !offsets)
			return corrupt("no TEMPLATE_OFFSETS section for tree " + std::to_string(t) +
				       " (uint8 templates)");
		if (!sparse && offsets)
			return corrupt(describe(*offsets) + ": float32 templates have no offsets");
		if (auto e = expectElement(*nodes, sizeof(TreeNode)))
			return *e;
		if (auto e = expectElement(*templ, perTemplate))
			return *e;
		if (auto e = expectElement(*votes, sizeof(PackedVote)))
			return *e;

		TreeView view;
		view.nodes = {reinterpret_cast<const TreeNode *>(base + nodes->offset),
			      nodes->elementCount};
		view.templates = base + templ->offset;
		view.votes = {reinterpret_cast<const PackedVote *>(base + votes->offset),
			      votes->elementCount};
		uint64_t templateCount = templ->elementCount;
		uint64_t bins = templateCount * dims;
		if (sparse) {
			if (auto e = expectElement(*offsets, sizeof(uint32_t)))
				return *e;
			view.templateOffsets = {reinterpret_cast<const uint32_t *>(base + offsets->offset),
						offsets->elementCount};
			templateCount = offsets->elementCount;
			bins = 0;
			if (auto bad = checkSparseTemplates(reinterpret_cast<const uint8_t *>(view.templates),
							    templ->size, view.templateOffsets,
							    sum.dims, bins))
				return corrupt("TEMPLATES of tree " + std::to_string(t) + ": " + *bad);
		}
		if (auto bad = checkVoteRotations(view.votes, sum.rotations))
			return corrupt("VOTES of tree " + std::to_string(t) + ": " + *bad);
		ForestTreeStats stats;
		if (auto bad = checkTree(view.nodes, templateCount, votes->elementCount, stats))
			return corrupt("tree " + std::to_string(t) + " " + *bad);
		stats.templateBins = bins;
		sum.trees.push_back(stats);
		model->trees_.push_back(view);
	}
	model->view_.rotations = {reinterpret_cast<const PackedRotation *>(base + rotSec.offset),
				  rotSec.elementCount};
	model->view_.dims = sum.dims;
	model->view_.encoding = sum.encoding;
	model->view_.trees = model->trees_;
	return std::unique_ptr<ObjectModel>(std::move(model));
}

Expected<ForestFileSummary> summariseModelFile(const fs::path &path)
{
	Expected<std::unique_ptr<ObjectModel>> model = loadModelFile(path);
	if (!model)
		return model.error();
	return static_cast<const MappedObjectModel &>(**model).summary();
}

} // namespace ihf
