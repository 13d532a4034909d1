// SPDX-License-Identifier: MIT
// PLY writing: binary little-endian (vertices, normals if present, faces),
// every face index checked first, written to a temporary file in the same
// folder and renamed into place.

#include <bit>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include <unistd.h>

#include "core/geometry/ply_loader.h"

namespace ihf {

Status savePly(const std::filesystem::path &path, const Mesh &mesh)
{
	const bool normals = mesh.hasNormals();
	if (!mesh.normals.empty() && !normals)
		return makeError(Errc::kInvalidArgument, path.string() + ": mesh has " + std::to_string(mesh.normals.size()) +
								 " normals for " + std::to_string(mesh.vertices.size()) + " vertices");
	for (size_t f = 0; f < mesh.faces.size(); ++f) {
		for (uint32_t idx : mesh.faces[f]) {
			if (idx >= mesh.vertices.size())
				return makeError(Errc::kOutOfRange, path.string() + ": face " + std::to_string(f) +
									    " index " + std::to_string(idx) + " out of range");
		}
	}

	std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by ihf\n";
	header += "element vertex " + std::to_string(mesh.vertices.size()) + "\n";
	header += "property float x\nproperty float y\nproperty float z\n";
	if (normals)
		header += "property float nx\nproperty float ny\nproperty float nz\n";
	header += "element face " + std::to_string(mesh.faces.size()) + "\n";
	header += "property list uchar int vertex_indices\nend_header\n";

	const size_t vertexBytes = normals ? 24 : 12;
	std::string out = header;
	out.reserve(header.size() + mesh.vertices.size() * vertexBytes + mesh.faces.size() * 13);

	auto put32 = [&out](uint32_t bits) {
		if constexpr (std::endian::native == std::endian::big)
			bits = ((bits & 0xffu) << 24) | ((bits & 0xff00u) << 8) | ((bits >> 8) & 0xff00u) | (bits >> 24);
		char b[4];
		std::memcpy(b, &bits, 4);
		out.append(b, 4);
	};
	auto putFloat = [&put32](float v) { put32(std::bit_cast<uint32_t>(v)); };

	for (size_t i = 0; i < mesh.vertices.size(); ++i) {
		for (int k = 0; k < 3; ++k)
			putFloat(mesh.vertices[i][k]);
		if (normals) {
			for (int k = 0; k < 3; ++k)
				putFloat(mesh.normals[i][k]);
		}
	}
	for (const auto &face : mesh.faces) {
		out.push_back(3);
		for (uint32_t idx : face)
			put32(idx);
	}

	// Temporary file in the same folder, renamed into place.
	std::filesystem::path tmp = path;
	tmp += ".tmp." + std::to_string(::getpid());
	{
		std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
		if (!f)
			return makeError(Errc::kIo, path.string() + ": cannot create " + tmp.string());
		f.write(out.data(), static_cast<std::streamsize>(out.size()));
		f.flush();
		if (!f) {
			f.close();
			std::filesystem::remove(tmp);
			return makeError(Errc::kIo, path.string() + ": write failed");
		}
	}
	std::error_code ec;
	std::filesystem::rename(tmp, path, ec);
	if (ec) {
		std::filesystem::remove(tmp);
		return makeError(Errc::kIo, path.string() + ": cannot rename temporary file: " + ec.message());
	}
	return {};
}

} // namespace ihf
