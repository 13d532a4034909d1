// SPDX-License-Identifier: MIT
#pragma once

// A Mesh written as the files users bring (STL ASCII and binary, OBJ,
// glTF with an embedded or external buffer, GLB), written here from the
// file formats' specifications and independently of the importer, so that
// tests can load the same mesh from every format and compare.

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geometry/mesh.h"

namespace ihf::test {

inline void writeBytes(const std::filesystem::path &path, const std::string &bytes)
{
	std::ofstream out(path, std::ios::binary | std::ios::trunc);
	out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline void appendLe32(std::string &out, uint32_t v)
{
	for (int i = 0; i < 4; ++i)
		out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

inline void appendFloat(std::string &out, float v) { appendLe32(out, std::bit_cast<uint32_t>(v)); }

// Shortest text that reads back as the same float.
inline std::string floatText(float v)
{
	char buf[32];
	std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
	return buf;
}

inline Eigen::Vector3f faceNormal(const Mesh &m, const std::array<uint32_t, 3> &f)
{
	const Eigen::Vector3f n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]);
	return n.norm() > 0 ? Eigen::Vector3f(n.normalized()) : Eigen::Vector3f::Zero();
}

inline std::string stlAscii(const Mesh &m)
{
	std::string s = "solid test\n";
	for (const auto &f : m.faces) {
		const Eigen::Vector3f n = faceNormal(m, f);
		s += "  facet normal " + floatText(n.x()) + " " + floatText(n.y()) + " " + floatText(n.z()) + "\n";
		s += "    outer loop\n";
		for (uint32_t v : f) {
			const Eigen::Vector3f &p = m.vertices[v];
			s += "      vertex " + floatText(p.x()) + " " + floatText(p.y()) + " " + floatText(p.z()) + "\n";
		}
		s += "    endloop\n  endfacet\n";
	}
	return s + "endsolid test\n";
}

inline std::string stlBinary(const Mesh &m)
{
	std::string s(80, '\0');
	std::memcpy(s.data(), "binary STL written by the ihf tests", 35);
	appendLe32(s, static_cast<uint32_t>(m.faces.size()));
	for (const auto &f : m.faces) {
		const Eigen::Vector3f n = faceNormal(m, f);
		for (int k = 0; k < 3; ++k)
			appendFloat(s, n[k]);
		for (uint32_t v : f)
			for (int k = 0; k < 3; ++k)
				appendFloat(s, m.vertices[v][k]);
		s.append(2, '\0'); // attribute byte count
	}
	return s;
}

inline std::string objText(const Mesh &m)
{
	std::string s = "# written by the ihf tests\no mesh\n";
	for (const auto &p : m.vertices)
		s += "v " + floatText(p.x()) + " " + floatText(p.y()) + " " + floatText(p.z()) + "\n";
	for (const auto &f : m.faces)
		s += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
	return s;
}

// The binary buffer of a glTF mesh: positions, then 32-bit indices.
inline std::string gltfBuffer(const Mesh &m)
{
	std::string b;
	for (const auto &p : m.vertices)
		for (int k = 0; k < 3; ++k)
			appendFloat(b, p[k]);
	for (const auto &f : m.faces)
		for (uint32_t v : f)
			appendLe32(b, v);
	return b;
}

// The glTF 2.0 JSON of one mesh in one node; `buffer` is the buffers[0]
// entry (with its uri, or without one for GLB).
inline nlohmann::json gltfJson(const Mesh &m, const nlohmann::json &buffer)
{
	using nlohmann::json;
	Eigen::Vector3f lo = m.vertices.empty() ? Eigen::Vector3f::Zero() : m.vertices[0];
	Eigen::Vector3f hi = lo;
	for (const auto &p : m.vertices) {
		lo = lo.cwiseMin(p);
		hi = hi.cwiseMax(p);
	}
	const size_t posBytes = m.vertices.size() * 12, idxBytes = m.faces.size() * 12;
	json j;
	j["asset"] = {{"version", "2.0"}, {"generator", "ihf tests"}};
	j["buffers"] = json::array({buffer});
	j["bufferViews"] = json::array({
		{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", posBytes}, {"target", 34962}},
		{{"buffer", 0}, {"byteOffset", posBytes}, {"byteLength", idxBytes}, {"target", 34963}},
	});
	j["accessors"] = json::array({
		{{"bufferView", 0}, {"componentType", 5126}, {"count", m.vertices.size()}, {"type", "VEC3"},
		 {"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}},
		{{"bufferView", 1}, {"componentType", 5125}, {"count", m.faces.size() * 3}, {"type", "SCALAR"}},
	});
	j["meshes"] = json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", 4}}})}}});
	j["nodes"] = json::array({{{"mesh", 0}}});
	j["scenes"] = json::array({{{"nodes", json::array({0})}}});
	j["scene"] = 0;
	return j;
}

inline std::string base64(const std::string &bytes)
{
	static const char *kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
	std::string out;
	size_t i = 0;
	for (; i + 2 < bytes.size(); i += 3) {
		const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
		for (int k = 3; k >= 0; --k)
			out.push_back(kDigits[(v >> (6 * k)) & 63]);
	}
	if (i + 1 == bytes.size()) {
		const uint32_t v = uint8_t(bytes[i]) << 16;
		out += {kDigits[(v >> 18) & 63], kDigits[(v >> 12) & 63], '=', '='};
	} else if (i + 2 == bytes.size()) {
		const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8);
		out += {kDigits[(v >> 18) & 63], kDigits[(v >> 12) & 63], kDigits[(v >> 6) & 63], '='};
	}
	return out;
}

// glTF with its buffer inside the JSON as a data: URI.
inline std::string gltfEmbedded(const Mesh &m)
{
	const std::string buf = gltfBuffer(m);
	return gltfJson(m, {{"byteLength", buf.size()},
			    {"uri", "data:application/octet-stream;base64," + base64(buf)}})
		.dump(1);
}

inline std::string glb(const Mesh &m)
{
	std::string bin = gltfBuffer(m);
	std::string js = gltfJson(m, {{"byteLength", bin.size()}}).dump();
	js.append((4 - js.size() % 4) % 4, ' ');
	bin.append((4 - bin.size() % 4) % 4, '\0');
	std::string s = "glTF";
	appendLe32(s, 2);
	appendLe32(s, static_cast<uint32_t>(12 + 8 + js.size() + 8 + bin.size()));
	appendLe32(s, static_cast<uint32_t>(js.size()));
	appendLe32(s, 0x4E4F534Au); // "JSON"
	s += js;
	appendLe32(s, static_cast<uint32_t>(bin.size()));
	appendLe32(s, 0x004E4942u); // "BIN\0"
	s += bin;
	return s;
}

} // namespace ihf::test
