// SPDX-License-Identifier: MIT
// loadMesh(): PLY through loadPly(), STL/OBJ/glTF through assimp (when the
// build has it). Assimp is a third-party parser of outside input, so it is
// fenced in: the file's size is checked before assimp opens it, every file
// assimp opens beside it (glTF buffers, OBJ materials) must be a regular
// file in the model's folder within the same byte budget, and the scene it
// returns is walked by us, not by its post-processing: node depth, instance
// counts, vertex and triangle counts are checked before anything of that
// size is allocated here, and every index and coordinate is checked.

#include "core/geometry/mesh_import.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <exception>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/geometry/ply_loader.h"

#include <nlohmann/json.hpp>

#if IHF_HAVE_ASSIMP
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

namespace ihf {

namespace fs = std::filesystem;

namespace {

enum class MeshFormat { kPly, kStl, kObj, kGltf, kUnknown };

MeshFormat formatOf(const fs::path &path)
{
	std::string ext = path.extension().string();
	std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
	if (ext == ".ply")
		return MeshFormat::kPly;
	if (ext == ".stl")
		return MeshFormat::kStl;
	if (ext == ".obj")
		return MeshFormat::kObj;
	if (ext == ".gltf" || ext == ".glb")
		return MeshFormat::kGltf;
	return MeshFormat::kUnknown;
}

#if IHF_HAVE_ASSIMP

// Deeper node trees than this are refused: real models nest a few levels,
// and the walk below recurses once per level.
constexpr int kMaxNodeDepth = 256;

// Deeper JSON nesting than this is refused before assimp parses a glTF
// (its JSON parser recurses once per level); real files nest under ten.
constexpr int kMaxJsonDepth = 64;

Expected<std::string> readWhole(const fs::path &path)
{
	std::ifstream in(path, std::ios::binary);
	if (!in)
		return makeError(Errc::kIo, "cannot open for reading");
	std::ostringstream buf;
	buf << in.rdbuf();
	if (in.bad())
		return makeError(Errc::kIo, "read error");
	return std::move(buf).str();
}

uint32_t le32(const std::string &b, size_t at)
{
	return uint32_t(uint8_t(b[at])) | uint32_t(uint8_t(b[at + 1])) << 8 | uint32_t(uint8_t(b[at + 2])) << 16 |
	       uint32_t(uint8_t(b[at + 3])) << 24;
}

// Deepest nesting of [ and { outside strings.
int jsonDepth(std::string_view text)
{
	int depth = 0, deepest = 0;
	bool inString = false;
	for (size_t i = 0; i < text.size(); ++i) {
		const char c = text[i];
		if (inString) {
			if (c == '\\')
				++i;
			else if (c == '"')
				inString = false;
		} else if (c == '"') {
			inString = true;
		} else if (c == '[' || c == '{') {
			deepest = std::max(deepest, ++depth);
		} else if (c == ']' || c == '}') {
			--depth;
		}
	}
	return deepest;
}

// Every mesh primitive's vertices: attributes.POSITION, an accessor's index,
// as glTF requires. assimp 5.2.5 reads a primitive without it through a
// null pointer (tests/data/fuzz/gltf_primitive_without_position.gltf).
Status checkGltfPositions(const nlohmann::json &j)
{
	const auto meshes = j.find("meshes");
	if (meshes == j.end() || !meshes->is_array())
		return {};
	const auto accessors = j.find("accessors");
	const size_t accessorCount = accessors != j.end() && accessors->is_array() ? accessors->size() : 0;
	for (size_t m = 0; m < meshes->size(); ++m) {
		const nlohmann::json &mesh = (*meshes)[m];
		const auto primitives = mesh.is_object() ? mesh.find("primitives") : mesh.end();
		if (!mesh.is_object() || primitives == mesh.end() || !primitives->is_array())
			continue;
		for (size_t p = 0; p < primitives->size(); ++p) {
			const nlohmann::json &prim = (*primitives)[p];
			const std::string where = "glTF: mesh " + std::to_string(m) + ", primitive " + std::to_string(p);
			const auto attributes = prim.is_object() ? prim.find("attributes") : prim.end();
			if (!prim.is_object() || attributes == prim.end() || !attributes->is_object())
				return makeError(Errc::kParse, where + ": no attributes");
			const auto position = attributes->find("POSITION");
			if (position == attributes->end())
				return makeError(Errc::kParse, where + ": no POSITION attribute (its vertices)");
			if (position->is_string())
				return makeError(Errc::kUnsupported, where + ": POSITION names its accessor, as glTF 1.0 "
								    "did; glTF 2.0 files are read");
			if (!position->is_number_unsigned() || position->get<uint64_t>() >= accessorCount)
				return makeError(Errc::kParse, where + ": POSITION is not the index of one of the " +
								   std::to_string(accessorCount) + " accessors");
		}
	}
	return {};
}

// What assimp's glTF importer trusts and we check first: the JSON's
// nesting, and that the nodes form trees, as glTF requires (a node that is
// the child of two nodes, or of itself, would make assimp copy it once per
// path, exponentially many, or recurse forever), no deeper than
// kMaxNodeDepth. `bytes` is the whole file, .gltf or .glb.
Status checkGltf(const std::string &bytes, bool binary, uint64_t maxNodes)
{
	std::string_view text = bytes;
	if (binary) {
		// GLB: 12-byte header, then the JSON chunk (length, type, data).
		if (bytes.size() < 20)
			return makeError(Errc::kParse, "GLB: file too short for its header and JSON chunk");
		const uint32_t length = le32(bytes, 12);
		if (le32(bytes, 16) != 0x4E4F534Au || length > bytes.size() - 20)
			return makeError(Errc::kParse, "GLB: the first chunk is not a whole JSON chunk");
		text = text.substr(20, length);
	}
	if (jsonDepth(text) > kMaxJsonDepth)
		return makeError(Errc::kUnsupported, "glTF JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
	const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
	if (j.is_discarded() || !j.is_object())
		return makeError(Errc::kParse, "glTF: not a JSON object");
	if (Status s = checkGltfPositions(j); !s)
		return s;
	const auto nodesIt = j.find("nodes");
	if (nodesIt == j.end() || !nodesIt->is_array())
		return {};
	const nlohmann::json &nodes = *nodesIt;
	if (nodes.size() > maxNodes)
		return makeError(Errc::kCapacity, "glTF: " + std::to_string(nodes.size()) + " nodes, more than the limit of " +
							  std::to_string(maxNodes));
	std::vector<int> parent(nodes.size(), -1);
	for (size_t n = 0; n < nodes.size(); ++n) {
		if (!nodes[n].is_object())
			continue;
		const auto children = nodes[n].find("children");
		if (children == nodes[n].end() || !children->is_array())
			continue;
		for (const auto &c : *children) {
			if (!c.is_number_unsigned() || c.get<uint64_t>() >= nodes.size())
				continue; // assimp refuses a bad index itself
			const size_t k = c.get<uint64_t>();
			if (parent[k] >= 0 || k == n)
				return makeError(Errc::kUnsupported, "glTF: node " + std::to_string(k) +
									 " has more than one parent (the nodes must form trees)");
			parent[k] = static_cast<int>(n);
		}
	}
	// One parent each: a node is in a cycle or too deep if its chain of
	// parents runs longer than kMaxNodeDepth.
	for (size_t n = 0; n < nodes.size(); ++n) {
		int depth = 0;
		for (int p = parent[n]; p >= 0; p = parent[p]) {
			if (++depth > kMaxNodeDepth)
				return makeError(Errc::kUnsupported, "glTF: node " + std::to_string(n) + " is deeper than " +
									     std::to_string(kMaxNodeDepth) +
									     " levels or in a cycle");
		}
	}
	return {};
}

// OBJ: the objects and groups ('o' and 'g' lines), each a node and a mesh
// in assimp, no more than maxNodes.
Status checkObj(std::string_view text, uint64_t maxNodes)
{
	uint64_t groups = 0;
	for (size_t at = 0; at < text.size();) {
		size_t end = text.find('\n', at);
		if (end == std::string_view::npos)
			end = text.size();
		const std::string_view line = text.substr(at, end - at);
		if (line.size() >= 2 && (line[0] == 'o' || line[0] == 'g') && (line[1] == ' ' || line[1] == '\t') &&
		    ++groups > maxNodes)
			return makeError(Errc::kCapacity, "OBJ: more than " + std::to_string(maxNodes) +
								  " objects and groups ('o', 'g' lines)");
		at = end + 1;
	}
	return {};
}

// The files assimp may open: regular files under the model's folder, each
// counted once against the byte budget. What was refused is kept so that
// the error can say why a buffer was missing.
class FencedIoSystem : public Assimp::DefaultIOSystem
{
public:
	FencedIoSystem(fs::path root, uint64_t maxBytes, std::string &refused)
		: root_(std::move(root)), maxBytes_(maxBytes), refused_(refused) {}

	Assimp::IOStream *Open(const char *file, const char *mode) override
	{
		if (file == nullptr || mode == nullptr)
			return nullptr;
		const std::string m(mode);
		if (m.find_first_of("wa+") != std::string::npos)
			return refuse(file, "opened for writing");
		std::error_code ec;
		const fs::path p = fs::weakly_canonical(fs::path(file), ec);
		if (ec || !fs::is_regular_file(p, ec))
			return refuse(file, "not a regular file");
		const auto [rootEnd, pEnd] = std::mismatch(root_.begin(), root_.end(), p.begin(), p.end());
		if (rootEnd != root_.end())
			return refuse(file, "outside the model's folder");
		if (!seen_.count(p.string())) {
			const uint64_t size = fs::file_size(p, ec);
			if (ec)
				return refuse(file, "size unknown");
			if (size > maxBytes_ - used_)
				return refuse(file, "over the byte budget of " + std::to_string(maxBytes_) + " bytes");
			used_ += size;
			seen_.insert(p.string());
		}
		return Assimp::DefaultIOSystem::Open(p.c_str(), mode);
	}

private:
	Assimp::IOStream *refuse(const char *file, const std::string &why)
	{
		if (refused_.empty())
			refused_ = std::string(file) + ": " + why;
		return nullptr;
	}

	fs::path root_;
	uint64_t maxBytes_;
	uint64_t used_ = 0;
	std::set<std::string> seen_;
	std::string &refused_;
};

struct Instance {
	const aiMesh *mesh;
	aiMatrix4x4 transform;
};

// Collects every mesh instance of the node tree with its world transform,
// counting vertices and triangle faces as it goes, and stops as soon as a
// limit is passed (a small file can instance a mesh many times).
class SceneWalk
{
public:
	SceneWalk(const aiScene &scene, const MeshImportLimits &limits) : scene_(scene), limits_(limits) {}

	Status walk(const aiNode *node, const aiMatrix4x4 &parent, int depth)
	{
		if (depth > kMaxNodeDepth)
			return makeError(Errc::kUnsupported, "node tree deeper than " + std::to_string(kMaxNodeDepth) + " levels");
		const aiMatrix4x4 world = parent * node->mTransformation;
		for (unsigned i = 0; i < node->mNumMeshes; ++i) {
			const unsigned m = node->mMeshes[i];
			if (m >= scene_.mNumMeshes || scene_.mMeshes[m] == nullptr)
				return makeError(Errc::kCorrupt, "node '" + std::string(node->mName.C_Str()) +
								 "' names mesh " + std::to_string(m) + " of " +
								 std::to_string(scene_.mNumMeshes));
			const aiMesh *mesh = scene_.mMeshes[m];
			vertices_ += mesh->mNumVertices;
			faces_ += mesh->mNumFaces;
			if (vertices_ > limits_.maxVertices)
				return makeError(Errc::kCapacity, "more than " + std::to_string(limits_.maxVertices) +
								  " vertices (mesh instances included)");
			if (faces_ > limits_.maxTriangles)
				return makeError(Errc::kCapacity, "more than " + std::to_string(limits_.maxTriangles) +
								  " faces (mesh instances included)");
			instances_.push_back({mesh, world});
		}
		for (unsigned i = 0; i < node->mNumChildren; ++i) {
			if (node->mChildren[i] == nullptr)
				continue;
			if (Status s = walk(node->mChildren[i], world, depth + 1); !s)
				return s;
		}
		return {};
	}

	const std::vector<Instance> &instances() const { return instances_; }
	uint64_t faces() const { return faces_; }
	uint64_t vertices() const { return vertices_; }

private:
	const aiScene &scene_;
	const MeshImportLimits &limits_;
	std::vector<Instance> instances_;
	uint64_t vertices_ = 0;
	uint64_t faces_ = 0;
};

// A position as a hash key: the bits of its three floats, -0 taken as 0.
struct PositionKey {
	std::array<uint32_t, 3> bits;
	bool operator==(const PositionKey &) const = default;
};

struct PositionHash {
	size_t operator()(const PositionKey &k) const
	{
		uint64_t h = 1469598103934665603ull;
		for (uint32_t b : k.bits)
			h = (h ^ b) * 1099511628211ull;
		return static_cast<size_t>(h ^ (h >> 29));
	}
};

PositionKey keyOf(const Eigen::Vector3f &p)
{
	PositionKey k;
	for (int i = 0; i < 3; ++i)
		k.bits[i] = std::bit_cast<uint32_t>(p[i] == 0.0f ? 0.0f : p[i]);
	return k;
}

// The triangles of every instance, corners at the same position joined,
// degenerate triangles dropped, vertices numbered in order of first use.
Expected<Mesh> buildMesh(const std::string &path, const SceneWalk &walk)
{
	Mesh welded;
	std::unordered_map<PositionKey, uint32_t, PositionHash> index;
	index.reserve(std::min<uint64_t>(walk.vertices(), 1u << 20));
	welded.faces.reserve(walk.faces());
	std::vector<uint32_t> local; // this instance's vertex -> welded vertex
	size_t nonTriangles = 0;
	for (const Instance &inst : walk.instances()) {
		const aiMesh &m = *inst.mesh;
		if (m.mNumVertices > 0 && m.mVertices == nullptr)
			return makeError(Errc::kCorrupt, path + ": mesh '" + std::string(m.mName.C_Str()) + "' has no positions");
		if (m.mNumFaces > 0 && m.mFaces == nullptr)
			return makeError(Errc::kCorrupt, path + ": mesh '" + std::string(m.mName.C_Str()) + "' has no face list");
		local.assign(m.mNumVertices, UINT32_MAX);
		for (unsigned f = 0; f < m.mNumFaces; ++f) {
			const aiFace &face = m.mFaces[f];
			if (face.mNumIndices != 3 || face.mIndices == nullptr) {
				++nonTriangles; // points and lines
				continue;
			}
			std::array<uint32_t, 3> tri;
			for (int c = 0; c < 3; ++c) {
				const unsigned v = face.mIndices[c];
				if (v >= m.mNumVertices)
					return makeError(Errc::kOutOfRange, path + ": mesh '" + std::string(m.mName.C_Str()) +
										   "' face " + std::to_string(f) + ": vertex index " +
										   std::to_string(v) + " of " + std::to_string(m.mNumVertices));
				if (local[v] == UINT32_MAX) {
					const aiVector3D p = inst.transform * m.mVertices[v];
					const Eigen::Vector3f q(p.x, p.y, p.z);
					if (!q.allFinite())
						return makeError(Errc::kCorrupt, path + ": mesh '" + std::string(m.mName.C_Str()) +
											 "' vertex " + std::to_string(v) +
											 ": coordinate is not finite");
					auto [it, added] = index.try_emplace(keyOf(q), static_cast<uint32_t>(welded.vertices.size()));
					if (added)
						welded.vertices.push_back(q);
					local[v] = it->second;
				}
				tri[c] = local[v];
			}
			welded.faces.push_back(tri);
		}
	}

	// Keep the faces that are triangles, and the vertices they use.
	Mesh mesh;
	std::vector<uint32_t> renumber(welded.vertices.size(), UINT32_MAX);
	mesh.faces.reserve(welded.faces.size());
	for (const auto &f : welded.faces) {
		if (isDegenerateFace(welded, f))
			continue;
		std::array<uint32_t, 3> g;
		for (int c = 0; c < 3; ++c) {
			if (renumber[f[c]] == UINT32_MAX) {
				renumber[f[c]] = static_cast<uint32_t>(mesh.vertices.size());
				mesh.vertices.push_back(welded.vertices[f[c]]);
			}
			g[c] = renumber[f[c]];
		}
		mesh.faces.push_back(g);
	}
	if (mesh.faces.empty())
		return makeError(Errc::kCorrupt, path + ": no triangles (" + std::to_string(welded.faces.size()) +
						 " degenerate, " + std::to_string(nonTriangles) + " points or lines)");
	return mesh;
}

Expected<Mesh> loadWithAssimp(const fs::path &path, const MeshImportLimits &limits)
{
	const std::string name = path.string();
	std::error_code ec;
	const fs::path file = fs::canonical(path, ec);
	if (ec)
		return makeError(Errc::kIo, name + ": cannot resolve the path: " + ec.message());

	if (const MeshFormat format = formatOf(path); format == MeshFormat::kGltf || format == MeshFormat::kObj) {
		auto bytes = readWhole(file);
		if (!bytes)
			return makeError(bytes.error().code, name + ": " + bytes.error().message);
		const bool binary = bytes->size() >= 4 && bytes->compare(0, 4, "glTF") == 0;
		Status s = format == MeshFormat::kObj ? checkObj(*bytes, limits.maxNodes)
						      : checkGltf(*bytes, binary, limits.maxNodes);
		if (!s)
			return makeError(s.error().code, name + ": " + s.error().message);
	}

	std::string refused;
	Assimp::Importer importer;
	importer.SetIOHandler(new FencedIoSystem(file.parent_path(), limits.maxFileBytes, refused));
	// Polygons triangulated by assimp. Node transforms, joining, the
	// degenerate test and the checks of every index are ours (SceneWalk,
	// buildMesh): no post-process allocates per instance before our limits,
	// and a file of points alone says "no triangles", not that a validation
	// failed.
	const unsigned flags = aiProcess_Triangulate;
	const aiScene *scene = nullptr;
	std::string what;
	try {
		scene = importer.ReadFile(file.string(), flags);
		if (!scene)
			what = importer.GetErrorString();
	} catch (const std::exception &e) {
		what = e.what();
	} catch (...) {
		what = "unknown exception";
	}
	if (!scene) {
		std::string msg = name + ": cannot read: " + (what.empty() ? std::string("assimp gave no reason") : what);
		if (!refused.empty())
			msg += " (refused to open " + refused + ")";
		return makeError(Errc::kParse, msg);
	}
	if (scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
		return makeError(Errc::kCorrupt, name + ": no triangles (the file holds no complete scene)");

	SceneWalk walk(*scene, limits);
	if (Status s = walk.walk(scene->mRootNode, aiMatrix4x4(), 0); !s)
		return makeError(s.error().code, name + ": " + s.error().message);
	return buildMesh(name, walk);
}

#endif // IHF_HAVE_ASSIMP

} // namespace

bool meshImportHasAssimp()
{
	return IHF_HAVE_ASSIMP != 0;
}

const char *meshImportFormats()
{
	return IHF_HAVE_ASSIMP ? "PLY, STL, OBJ, glTF (.gltf, .glb)" : "PLY";
}

Expected<Mesh> loadMesh(const fs::path &path, const MeshImportLimits &limits)
{
	const MeshFormat format = formatOf(path);
	if (format == MeshFormat::kPly)
		return loadPly(path);
	if (format == MeshFormat::kUnknown)
		return makeError(Errc::kUnsupported, path.string() + ": unknown mesh format '" + path.extension().string() +
							     "' (reads " + meshImportFormats() + ")");

	std::error_code ec;
	if (!fs::is_regular_file(path, ec))
		return makeError(Errc::kNotFound, path.string() + ": no such file");
	const uint64_t size = fs::file_size(path, ec);
	if (ec)
		return makeError(Errc::kIo, path.string() + ": cannot read the size: " + ec.message());
	if (size == 0)
		return makeError(Errc::kParse, path.string() + ": empty file");
	if (size > limits.maxFileBytes)
		return makeError(Errc::kCapacity, path.string() + ": file of " + std::to_string(size) +
							  " bytes, more than the limit of " + std::to_string(limits.maxFileBytes));
#if IHF_HAVE_ASSIMP
	return loadWithAssimp(path, limits);
#else
	return makeError(Errc::kUnsupported, path.string() + ": built without assimp: STL/OBJ/glTF need libassimp-dev "
							     "(or convert the mesh to PLY)");
#endif
}

} // namespace ihf
