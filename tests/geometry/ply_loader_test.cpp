// SPDX-License-Identifier: MIT
// PLY reading and writing: the shared LM-O models, every supported layout,
// round trips, and the errors for broken files.

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/geometry/ply_loader.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path &path)
{
	std::ifstream in(path, std::ios::binary);
	std::ostringstream s;
	s << in.rdbuf();
	return s.str();
}

void writeText(const fs::path &path, const std::string &text)
{
	std::ofstream out(path, std::ios::binary);
	out << text;
}

// Element counts as declared in a PLY header, read independently of the loader.
std::map<std::string, size_t> headerCounts(const fs::path &path)
{
	std::map<std::string, size_t> counts;
	std::ifstream in(path);
	std::string line;
	while (std::getline(in, line) && line != "end_header") {
		std::istringstream w(line);
		std::string key, name;
		size_t n;
		if (w >> key >> name >> n && key == "element")
			counts[name] = n;
	}
	return counts;
}

bool sameMesh(const Mesh &a, const Mesh &b)
{
	if (a.vertices.size() != b.vertices.size() || a.normals.size() != b.normals.size() ||
	    a.faces.size() != b.faces.size())
		return false;
	for (size_t i = 0; i < a.vertices.size(); ++i) {
		if (a.vertices[i] != b.vertices[i])
			return false;
	}
	for (size_t i = 0; i < a.normals.size(); ++i) {
		if (a.normals[i] != b.normals[i])
			return false;
	}
	return a.faces == b.faces;
}

// A small mesh: a unit square (two triangles) and a tetrahedron beside it.
Mesh smallMesh()
{
	Mesh m;
	m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {3, 0, 0}, {4, 0, 0}, {3, 1, 0}, {3, 0, 1.5f}};
	for (const auto &v : m.vertices)
		m.normals.push_back(Eigen::Vector3f(v.x(), -v.y(), 0.25f).normalized());
	m.faces = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 5, 7}, {5, 6, 7}, {4, 6, 7}};
	return m;
}

std::string asciiPly(const Mesh &m)
{
	std::string s = "ply\nformat ascii 1.0\ncomment test\nelement vertex " + std::to_string(m.vertices.size()) +
			"\nproperty float x\nproperty float y\nproperty float z\n"
			"property float nx\nproperty float ny\nproperty float nz\n"
			"property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
			"element face " + std::to_string(m.faces.size()) +
			"\nproperty list uchar int vertex_indices\nend_header\n";
	char buf[256];
	for (size_t i = 0; i < m.vertices.size(); ++i) {
		const auto &v = m.vertices[i];
		const auto &n = m.normals[i];
		std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g %.9g %.9g %.9g 10 20 30 255 \n", v.x(), v.y(), v.z(),
			      n.x(), n.y(), n.z());
		s += buf;
	}
	for (const auto &f : m.faces)
		s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
	return s;
}

// Appends a value in big- or little-endian byte order.
template<typename T>
void put(std::string &out, T value, bool bigEndian)
{
	char b[sizeof(T)];
	std::memcpy(b, &value, sizeof(T));
	if (bigEndian)
		std::reverse(b, b + sizeof(T));
	out.append(b, sizeof(T));
}

class PlyTest : public ::testing::Test
{
protected:
	void SetUp() override { dir_ = test::freshTempDir("ply_" + std::string(
		::testing::UnitTest::GetInstance()->current_test_info()->name())); }
	fs::path dir_;
};

TEST_F(PlyTest, LoadsEveryLmoModel)
{
	const fs::path models = test::lmoDir() / "models";
	nlohmann::json info;
	std::ifstream(models / "models_info.json") >> info;
	int loaded = 0;
	for (const auto &[key, entry] : info.items()) {
		char name[32];
		std::snprintf(name, sizeof(name), "obj_%06d.ply", std::stoi(key));
		const fs::path path = models / name;
		SCOPED_TRACE(path.string());
		auto mesh = loadPly(path);
		ASSERT_TRUE(mesh.ok()) << mesh.error().message;
		auto counts = headerCounts(path);
		EXPECT_EQ(mesh->vertices.size(), counts["vertex"]);
		EXPECT_EQ(mesh->faces.size(), counts["face"]); // all triangles
		EXPECT_TRUE(mesh->hasNormals());
		const double diameter = entry["diameter"].get<double>();
		EXPECT_NEAR(meshDiameter(*mesh), diameter, 0.005 * diameter);
		const Aabb box = boundingBox(*mesh);
		EXPECT_NEAR(box.min.x(), entry["min_x"].get<double>(), 0.01);
		EXPECT_NEAR(box.min.y(), entry["min_y"].get<double>(), 0.01);
		EXPECT_NEAR(box.min.z(), entry["min_z"].get<double>(), 0.01);
		EXPECT_NEAR(box.size().x(), entry["size_x"].get<double>(), 0.01);
		EXPECT_NEAR(box.size().y(), entry["size_y"].get<double>(), 0.01);
		EXPECT_NEAR(box.size().z(), entry["size_z"].get<double>(), 0.01);
		EXPECT_LT(countDegenerateFaces(*mesh), mesh->faces.size() / 100);
		++loaded;
	}
	EXPECT_EQ(loaded, 8);
}

TEST_F(PlyTest, FirstLmoVertexMatchesFileText)
{
	const fs::path path = test::lmoDir() / "models" / "obj_000001.ply";
	std::istringstream text(readText(path));
	std::string line;
	while (std::getline(text, line) && line != "end_header") {
	}
	std::getline(text, line);
	std::istringstream first(line);
	float v[6];
	for (float &x : v)
		first >> x;
	auto mesh = loadPly(path);
	ASSERT_TRUE(mesh.ok());
	EXPECT_EQ(mesh->vertices[0], Eigen::Vector3f(v[0], v[1], v[2]));
	EXPECT_EQ(mesh->normals[0], Eigen::Vector3f(v[3], v[4], v[5]));
}

TEST_F(PlyTest, BinaryRoundTripOfLmoModel)
{
	auto ascii = loadPly(test::lmoDir() / "models" / "obj_000005.ply");
	ASSERT_TRUE(ascii.ok());
	const fs::path out = dir_ / "can.ply";
	ASSERT_TRUE(savePly(out, *ascii).ok());
	EXPECT_EQ(readText(out).rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
	auto binary = loadPly(out);
	ASSERT_TRUE(binary.ok()) << binary.error().message;
	EXPECT_TRUE(sameMesh(*ascii, *binary));
	// No temporary left behind.
	EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(PlyTest, RoundTripWithoutNormals)
{
	Mesh m = smallMesh();
	m.normals.clear();
	ASSERT_TRUE(savePly(dir_ / "m.ply", m).ok());
	auto back = loadPly(dir_ / "m.ply");
	ASSERT_TRUE(back.ok()) << back.error().message;
	EXPECT_FALSE(back->hasNormals());
	EXPECT_TRUE(sameMesh(m, *back));
}

TEST_F(PlyTest, AsciiAndBinaryGiveTheSameMesh)
{
	const Mesh m = smallMesh();
	writeText(dir_ / "a.ply", asciiPly(m));
	ASSERT_TRUE(savePly(dir_ / "b.ply", m).ok());
	auto a = loadPly(dir_ / "a.ply");
	auto b = loadPly(dir_ / "b.ply");
	ASSERT_TRUE(a.ok()) << a.error().message;
	ASSERT_TRUE(b.ok()) << b.error().message;
	EXPECT_TRUE(sameMesh(*a, m));
	EXPECT_TRUE(sameMesh(*a, *b));
}

// Big-endian body, odd property types, an extra element, a quad and a
// pentagon, 'vertex_index' with ushort counts and uint indices.
std::string exoticBinary(bool bigEndian)
{
	std::string s = std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
			" 1.0\ncomment exotic\nobj_info made by hand\n"
			"element material 1\nproperty uchar ambient_red\nproperty list uchar float coeffs\n"
			"element vertex 6\nproperty double x\nproperty char flag\nproperty float y\nproperty short s\n"
			"property float z\nproperty list uint uchar extra\nproperty float u\nproperty float v\n"
			"element face 2\nproperty uchar tag\nproperty list ushort uint vertex_index\nproperty int id\n"
			"element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
	put<uint8_t>(s, 7, bigEndian);
	put<uint8_t>(s, 2, bigEndian);
	put<float>(s, 0.5f, bigEndian);
	put<float>(s, 0.25f, bigEndian);
	const float xy[6][3] = {{0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}, {5, 0, 2}, {6, 1, 2}};
	for (int i = 0; i < 6; ++i) {
		put<double>(s, xy[i][0], bigEndian);
		put<int8_t>(s, -3, bigEndian);
		put<float>(s, xy[i][1], bigEndian);
		put<int16_t>(s, -300, bigEndian);
		put<float>(s, xy[i][2], bigEndian);
		put<uint32_t>(s, static_cast<uint32_t>(i % 3), bigEndian);
		for (int k = 0; k < i % 3; ++k)
			put<uint8_t>(s, 9, bigEndian);
		put<float>(s, 0.1f * i, bigEndian);
		put<float>(s, 0.2f * i, bigEndian);
	}
	put<uint8_t>(s, 1, bigEndian);
	put<uint16_t>(s, 4, bigEndian);
	for (uint32_t i : {0u, 1u, 2u, 3u})
		put<uint32_t>(s, i, bigEndian);
	put<int32_t>(s, 100, bigEndian);
	put<uint8_t>(s, 2, bigEndian);
	put<uint16_t>(s, 5, bigEndian);
	for (uint32_t i : {4u, 5u, 2u, 1u, 0u})
		put<uint32_t>(s, i, bigEndian);
	put<int32_t>(s, 101, bigEndian);
	put<int32_t>(s, 0, bigEndian);
	put<int32_t>(s, 1, bigEndian);
	return s;
}

void expectExoticMesh(const Mesh &m)
{
	ASSERT_EQ(m.vertices.size(), 6u);
	EXPECT_FALSE(m.hasNormals());
	EXPECT_EQ(m.vertices[1], Eigen::Vector3f(2, 0, 1));
	EXPECT_EQ(m.vertices[5], Eigen::Vector3f(6, 1, 2));
	// Quad -> 2 triangles, pentagon -> 3, fanned from the first index.
	const std::vector<std::array<uint32_t, 3>> faces = {{0, 1, 2}, {0, 2, 3}, {4, 5, 2}, {4, 2, 1}, {4, 1, 0}};
	EXPECT_EQ(m.faces, faces);
}

TEST_F(PlyTest, BinaryLittleEndianWithOddLayout)
{
	writeText(dir_ / "le.ply", exoticBinary(false));
	auto m = loadPly(dir_ / "le.ply");
	ASSERT_TRUE(m.ok()) << m.error().message;
	expectExoticMesh(*m);
}

TEST_F(PlyTest, BinaryBigEndianWithOddLayout)
{
	writeText(dir_ / "be.ply", exoticBinary(true));
	auto m = loadPly(dir_ / "be.ply");
	ASSERT_TRUE(m.ok()) << m.error().message;
	expectExoticMesh(*m);
}

TEST_F(PlyTest, AsciiWithOddLayoutAndCrlf)
{
	std::string s = "ply\r\nformat ascii 1.0\r\ncomment crlf\r\n"
			"element vertex 5\r\nproperty int x\r\nproperty uchar red\r\nproperty double y\r\n"
			"property list uchar int junk\r\nproperty float z\r\nproperty float s\r\nproperty float t\r\n"
			"element face 2\r\nproperty list int short vertex_index\r\nproperty uchar flags\r\n"
			"element edge 1\r\nproperty int a\r\nproperty int b\r\nend_header\r\n"
			"0 1 0 0 5 0 0\r\n"
			"2 1 0 2 7 8 5 0.5 0.5\r\n"
			"\r\n"
			"2\t1 2.5 0 5 1 1\r\n"
			"0 1 2.5e0 1 3 5 0 1\r\n"
			"9 1 -1 0 -4.25 0 0\r\n"
			"4 0 1 2 3 1\r\n"
			"3 4 0 1 0\r\n"
			"0 1\r\n";
	writeText(dir_ / "odd.ply", s);
	auto m = loadPly(dir_ / "odd.ply");
	ASSERT_TRUE(m.ok()) << m.error().message;
	ASSERT_EQ(m->vertices.size(), 5u);
	EXPECT_EQ(m->vertices[2], Eigen::Vector3f(2, 2.5f, 5));
	EXPECT_EQ(m->vertices[4], Eigen::Vector3f(9, -1, -4.25f));
	const std::vector<std::array<uint32_t, 3>> faces = {{0, 1, 2}, {0, 2, 3}, {4, 0, 1}};
	EXPECT_EQ(m->faces, faces);
}

// Each broken file must fail with a message naming the file and the place.
struct BadCase {
	const char *name;
	std::string text;
	Errc code;
	std::vector<std::string> mentions;
};

std::string header(const std::string &format, int nv, int nf, const std::string &extraVertexProps = "")
{
	return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(nv) +
	       "\nproperty float x\nproperty float y\nproperty float z\n" + extraVertexProps + "element face " +
	       std::to_string(nf) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

TEST_F(PlyTest, BrokenFilesNameFileAndPlace)
{
	const std::string okVerts = "0 0 0\n1 0 0\n0 1 0\n";
	std::string binTrunc = header("binary_little_endian", 3, 1);
	for (int i = 0; i < 7; ++i)
		put<float>(binTrunc, 1.0f, false);
	std::string binFaceTrunc = header("binary_little_endian", 3, 1);
	for (int i = 0; i < 9; ++i)
		put<float>(binFaceTrunc, 1.0f, false);
	put<uint8_t>(binFaceTrunc, 3, false);
	put<int32_t>(binFaceTrunc, 0, false);
	std::string binBadIndex = binFaceTrunc;
	put<int32_t>(binBadIndex, 1, false);
	put<int32_t>(binBadIndex, 3, false);
	std::string binNan = header("binary_little_endian", 1, 0);
	put<float>(binNan, 0.0f, false);
	put<float>(binNan, std::nanf(""), false);
	put<float>(binNan, 0.0f, false);

	const std::vector<BadCase> cases = {
		{"empty.ply", "", Errc::kParse, {"empty"}},
		{"magic.ply", "plx\nformat ascii 1.0\nend_header\n", Errc::kParse, {"line 1", "magic"}},
		{"noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", Errc::kParse, {"end_header"}},
		{"format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", Errc::kUnsupported, {"header line 2"}},
		{"type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", Errc::kParse,
		 {"header line 4", "float128"}},
		{"novertex.ply", "ply\nformat ascii 1.0\nend_header\n", Errc::kParse, {"vertex"}},
		{"noz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
		 Errc::kParse, {"x, y, z"}},
		{"badcount.ply", "ply\nformat ascii 1.0\nelement vertex many\nend_header\n", Errc::kParse, {"'vertex'", "many"}},
		{"trunc.ply", header("ascii", 3, 1) + "0 0 0\n1 0 0\n", Errc::kCorrupt, {"truncated", "'vertex'", "2 of 3"}},
		{"truncface.ply", header("ascii", 3, 2) + okVerts + "3 0 1 2\n", Errc::kCorrupt, {"truncated", "'face'"}},
		{"shortline.ply", header("ascii", 3, 1) + "0 0 0\n1 0\n0 1 0\n3 0 1 2\n", Errc::kParse,
		 {"line 11", "'vertex'", "'z'"}},
		{"longline.ply", header("ascii", 3, 1) + "0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", Errc::kParse,
		 {"line 10", "more values"}},
		{"word.ply", header("ascii", 3, 1) + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", Errc::kParse,
		 {"line 11", "'y'"}},
		{"index.ply", header("ascii", 3, 1) + okVerts + "3 0 1 3\n", Errc::kOutOfRange,
		 {"line 13", "'face'", "vertex_indices", "index 3"}},
		{"negindex.ply", header("ascii", 3, 1) + okVerts + "3 0 -1 2\n", Errc::kOutOfRange, {"line 13", "-1"}},
		{"shortlist.ply", header("ascii", 3, 1) + okVerts + "4 0 1 2\n", Errc::kParse, {"line 13", "fewer than 4"}},
		{"twogon.ply", header("ascii", 3, 1) + okVerts + "2 0 1\n", Errc::kCorrupt, {"line 13", "need at least 3"}},
		{"nan.ply", header("ascii", 3, 1) + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", Errc::kCorrupt,
		 {"line 11", "'vertex' item 1", "'y'", "non-finite"}},
		{"inf.ply", header("ascii", 3, 1) + "0 0 inf\n1 0 0\n0 1 0\n3 0 1 2\n", Errc::kCorrupt,
		 {"line 10", "non-finite"}},
		{"extra.ply", header("ascii", 3, 1) + okVerts + "3 0 1 2\n1 2 3\n", Errc::kParse, {"line 14", "after the last"}},
		{"bintrunc.ply", binTrunc, Errc::kCorrupt, {"truncated", "'vertex' item 2", "'y'"}},
		{"binfacetrunc.ply", binFaceTrunc, Errc::kCorrupt, {"truncated", "'face' item 0", "vertex_indices"}},
		{"binindex.ply", binBadIndex, Errc::kOutOfRange, {"'face' item 0", "index 3"}},
		{"binnan.ply", binNan, Errc::kCorrupt, {"'vertex' item 0", "'y'", "non-finite"}},
		{"hugelist.ply", header("ascii", 3, 1) + okVerts + "250 0 1 2\n", Errc::kParse, {"line 13", "fewer than 250"}},
		{"huge.ply", header("binary_little_endian", 2000000000, 0) + "abc", Errc::kCorrupt, {"truncated", "'vertex'"}},
	};
	for (const BadCase &c : cases) {
		SCOPED_TRACE(c.name);
		const fs::path path = dir_ / c.name;
		writeText(path, c.text);
		auto m = loadPly(path);
		ASSERT_FALSE(m.ok());
		EXPECT_EQ(m.error().code, c.code) << m.error().message;
		EXPECT_NE(m.error().message.find(path.string()), std::string::npos) << m.error().message;
		for (const std::string &word : c.mentions)
			EXPECT_NE(m.error().message.find(word), std::string::npos) << m.error().message << " lacks " << word;
	}
}

// Headers that lie about the body (inputs found by tests/fuzz/fuzz_ply):
// the body must start after end_header's line break and stay inside the
// file, huge counts fail on the first missing byte, and an element without
// properties takes no bytes whatever its count.
TEST_F(PlyTest, LyingHeadersAreRefusedWithoutRunaway)
{
	const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
	const std::string bin = "ply\nformat binary_little_endian 1.0\n";
	struct Case {
		std::string name, text;
		std::vector<std::string> mentions;
	};
	const std::vector<Case> cases = {
		// Read 100 vertices of heap memory past the end of the file.
		{"endheader.ply", bin + "element vertex 100\n" + xyz + "end_header", {"header line 7", "'end_header' has no line break"}},
		// Aborted on std::length_error reserving the faces.
		{"endheader_faces.ply",
		 bin + "element vertex 3\n" + xyz + "element face 4000000000\nproperty list uchar int vertex_indices\nend_header",
		 {"'end_header' has no line break"}},
		{"ascii_endheader.ply", "ply\nformat ascii 1.0\nelement vertex 0\n" + xyz + "end_header", {"'end_header'"}},
		{"huge_faces.ply",
		 bin + "element vertex 0\n" + xyz + "element face 18446744073709551615\nproperty list uchar int vertex_indices\nend_header\n",
		 {"truncated", "'face' item 0"}},
	};
	for (const Case &c : cases) {
		SCOPED_TRACE(c.name);
		const fs::path path = dir_ / c.name;
		writeText(path, c.text);
		auto m = loadPly(path);
		ASSERT_FALSE(m.ok());
		EXPECT_EQ(m.error().code, Errc::kCorrupt) << m.error().message;
		EXPECT_NE(m.error().message.find(path.string()), std::string::npos) << m.error().message;
		for (const std::string &word : c.mentions)
			EXPECT_NE(m.error().message.find(word), std::string::npos) << m.error().message << " lacks " << word;
	}

	// Looped 2^64 - 1 times over an element of no bytes.
	std::string empty = bin + "element vertex 1\n" + xyz + "element nothing 18446744073709551615\nend_header\n";
	for (float v : {1.0f, 2.0f, 3.0f})
		put<float>(empty, v, false);
	writeText(dir_ / "empty_element.ply", empty);
	auto m = loadPly(dir_ / "empty_element.ply");
	ASSERT_TRUE(m.ok()) << m.error().message;
	ASSERT_EQ(m->vertices.size(), 1u);
	EXPECT_EQ(m->vertices[0], Eigen::Vector3f(1, 2, 3));
}

TEST_F(PlyTest, TruncatedCopiesOfARealModelFail)
{
	auto full = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
	ASSERT_TRUE(full.ok());
	ASSERT_TRUE(savePly(dir_ / "bin.ply", *full).ok());
	for (const char *name : {"obj_ascii.ply", "bin.ply"}) {
		const std::string text = std::string(name) == "bin.ply"
						 ? readText(dir_ / "bin.ply")
						 : readText(test::lmoDir() / "models" / "obj_000001.ply");
		for (double keep : {0.1, 0.5, 0.999}) {
			const fs::path path = dir_ / ("cut_" + std::to_string(keep) + name);
			writeText(path, text.substr(0, static_cast<size_t>(text.size() * keep)));
			auto m = loadPly(path);
			ASSERT_FALSE(m.ok()) << path;
			EXPECT_NE(m.error().message.find(path.string()), std::string::npos) << m.error().message;
		}
	}
}

TEST_F(PlyTest, MissingFileIsNotFound)
{
	const fs::path path = dir_ / "does_not_exist.ply";
	auto m = loadPly(path);
	ASSERT_FALSE(m.ok());
	EXPECT_EQ(m.error().code, Errc::kNotFound);
	EXPECT_NE(m.error().message.find(path.string()), std::string::npos);
}

TEST_F(PlyTest, SaveRejectsBadMeshAndLeavesNothing)
{
	Mesh m = smallMesh();
	m.faces.push_back({0, 1, 99});
	const fs::path path = dir_ / "bad.ply";
	Status s = savePly(path, m);
	ASSERT_FALSE(s.ok());
	EXPECT_EQ(s.error().code, Errc::kOutOfRange);
	EXPECT_FALSE(fs::exists(path));
	// Unwritable destination: error, no file.
	Status s2 = savePly(dir_ / "no_such_dir" / "x.ply", smallMesh());
	ASSERT_FALSE(s2.ok());
	EXPECT_NE(s2.error().message.find("x.ply"), std::string::npos);
}

} // namespace
} // namespace ihf
