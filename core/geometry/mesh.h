// SPDX-License-Identifier: MIT
#pragma once

// Triangle mesh in model coordinates (millimetres for BOP models).

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace ihf {

struct Mesh {
	std::vector<Eigen::Vector3f> vertices;
	std::vector<Eigen::Vector3f> normals; // empty, or one per vertex
	std::vector<std::array<uint32_t, 3>> faces;

	bool hasNormals() const { return !normals.empty() && normals.size() == vertices.size(); }
};

struct Aabb {
	Eigen::Vector3f min = Eigen::Vector3f::Zero();
	Eigen::Vector3f max = Eigen::Vector3f::Zero();
	Eigen::Vector3f size() const { return max - min; }
	Eigen::Vector3f centre() const { return 0.5f * (min + max); }
};

Aabb boundingBox(const Mesh &mesh);

// Largest distance between two vertices (BOP's "diameter"), exact.
double meshDiameter(const Mesh &mesh);

// Faces with repeated indices or (near) zero area: skipped by the renderer
// and the samplers; counted so loaders can report them.
size_t countDegenerateFaces(const Mesh &mesh);

// Whether one face is degenerate in the sense of countDegenerateFaces(): an
// index out of range or repeated, or an area within float rounding of zero.
bool isDegenerateFace(const Mesh &mesh, const std::array<uint32_t, 3> &face);

// Whether the mesh is closed, consistently wound and wound outwards (a
// positive volume): seen from outside, its back faces then always lie
// behind its front faces (DepthRenderer::setCullBackFaces()).
bool isClosedOutward(const Mesh &mesh);

// Turns faces so that a closed mesh is wound consistently and outwards
// (scanned models have a few faces the wrong way round: the LM-O can and
// eggbox); true if the mesh is then closed and outward. A mesh that is open
// or cannot be oriented may be partly turned and gives false. Allocates
// (load time).
bool orientClosedOutward(Mesh &mesh);

} // namespace ihf
