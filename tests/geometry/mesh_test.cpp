// SPDX-License-Identifier: MIT
// Mesh measures: bounding box, exact diameter (against brute force), and
// degenerate-face counting.

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/geometry/mesh.h"
#include "core/geometry/ply_loader.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

double bruteDiameter(const Mesh &m)
{
	double best = 0;
	for (size_t i = 0; i < m.vertices.size(); ++i)
		for (size_t j = i + 1; j < m.vertices.size(); ++j)
			best = std::max(best, (m.vertices[i].cast<double>() - m.vertices[j].cast<double>()).norm());
	return best;
}

TEST(Mesh, BoundingBox)
{
	Mesh m;
	EXPECT_EQ(boundingBox(m).size(), Eigen::Vector3f::Zero());
	m.vertices = {{1, -2, 3}, {-4, 5, 0.5f}, {2, 2, -7}};
	const Aabb box = boundingBox(m);
	EXPECT_EQ(box.min, Eigen::Vector3f(-4, -2, -7));
	EXPECT_EQ(box.max, Eigen::Vector3f(2, 5, 3));
	EXPECT_EQ(box.centre(), Eigen::Vector3f(-1, 1.5f, -2));
}

TEST(Mesh, DiameterOfSmallSets)
{
	Mesh m;
	EXPECT_EQ(meshDiameter(m), 0.0);
	m.vertices = {{1, 1, 1}};
	EXPECT_EQ(meshDiameter(m), 0.0);
	m.vertices = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
	EXPECT_EQ(meshDiameter(m), 0.0);
	m.vertices = {{0, 0, 0}, {3, 4, 0}};
	EXPECT_DOUBLE_EQ(meshDiameter(m), 5.0);
	// Unit cube corners: the space diagonal.
	m.vertices.clear();
	for (int i = 0; i < 8; ++i)
		m.vertices.push_back(Eigen::Vector3f(i & 1, (i >> 1) & 1, (i >> 2) & 1));
	EXPECT_DOUBLE_EQ(meshDiameter(m), std::sqrt(3.0));
}

TEST(Mesh, DiameterMatchesBruteForceOnRandomClouds)
{
	std::mt19937 rng(7);
	std::normal_distribution<float> gauss;
	std::uniform_real_distribution<float> uni(-1, 1);
	for (int trial = 0; trial < 12; ++trial) {
		Mesh m;
		const int n = 200 + 150 * trial;
		for (int i = 0; i < n; ++i) {
			Eigen::Vector3f p;
			switch (trial % 4) {
			case 0: // blob
				p = {gauss(rng), gauss(rng), gauss(rng)};
				break;
			case 1: // sphere shell: nothing to prune
				p = Eigen::Vector3f(gauss(rng), gauss(rng), gauss(rng)).normalized() * 50.0f;
				break;
			case 2: // elongated box, offset from the origin
				p = Eigen::Vector3f(100 + 80 * uni(rng), 5 * uni(rng), -300 + 20 * uni(rng));
				break;
			default: // two clusters far apart
				p = Eigen::Vector3f(uni(rng), uni(rng), uni(rng)) + (i % 2 ? Eigen::Vector3f(30, 10, 0)
											      : Eigen::Vector3f::Zero());
			}
			m.vertices.push_back(p);
		}
		SCOPED_TRACE(trial);
		EXPECT_DOUBLE_EQ(meshDiameter(m), bruteDiameter(m));
	}
}

TEST(Mesh, DiameterOfLmoApeMatchesBruteForce)
{
	auto mesh = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
	ASSERT_TRUE(mesh.ok()) << mesh.error().message;
	EXPECT_DOUBLE_EQ(meshDiameter(*mesh), bruteDiameter(*mesh));
}

TEST(Mesh, CountsDegenerateFaces)
{
	Mesh m;
	m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {0.5f, 0, 0}, {1e-3f, 1e-3f, 0}};
	m.faces = {
		{0, 1, 2}, // fine
		{0, 0, 2}, // repeated index
		{1, 2, 1}, // repeated index
		{0, 1, 3}, // collinear
		{0, 4, 1}, // collinear
		{0, 1, 5}, // thin but real
		{0, 1, 9}, // index out of range
	};
	EXPECT_EQ(countDegenerateFaces(m), 5u);
}

// Closed, oriented and wound outwards: a tetrahedron and a closed LM-O mesh
// are; a flipped face, a missing face or all faces turned inwards are not.
// A degenerate face (a repeated index) is left out of the check.
TEST(Mesh, ClosedOutwardNeedsEveryEdgeTwiceOppositeWaysAndAPositiveVolume)
{
	Mesh tet;
	tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
	tet.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
	EXPECT_TRUE(isClosedOutward(tet));

	Mesh flipped = tet;
	std::swap(flipped.faces[1][1], flipped.faces[1][2]);
	EXPECT_FALSE(isClosedOutward(flipped));

	Mesh open = tet;
	open.faces.pop_back();
	EXPECT_FALSE(isClosedOutward(open));

	Mesh inward = tet;
	for (auto &f : inward.faces)
		std::swap(f[1], f[2]);
	EXPECT_FALSE(isClosedOutward(inward));

	Mesh degenerate = tet;
	degenerate.faces.push_back({2, 2, 3});
	EXPECT_TRUE(isClosedOutward(degenerate));

	Mesh badIndex = tet;
	badIndex.faces.push_back({0, 1, 9});
	EXPECT_FALSE(isClosedOutward(badIndex));
	EXPECT_FALSE(isClosedOutward(Mesh{}));

	auto ape = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
	ASSERT_TRUE(ape.ok());
	EXPECT_TRUE(isClosedOutward(*ape));
}

// Faces wound the wrong way round are turned, a shell wound inwards turns
// whole, each shell on its own; an open mesh is not made closed. The LM-O
// can has a few faces the wrong way round and is closed after.
TEST(Mesh, OrientingTurnsTheFewWrongFacesAndInwardShells)
{
	Mesh tet;
	tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
	tet.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

	Mesh flipped = tet;
	std::swap(flipped.faces[1][1], flipped.faces[1][2]);
	ASSERT_FALSE(isClosedOutward(flipped));
	EXPECT_TRUE(orientClosedOutward(flipped));
	EXPECT_EQ(flipped.faces, tet.faces);

	// Two shells, the second (moved away) wound inwards with a face the
	// other way round again.
	Mesh two = tet;
	for (const Eigen::Vector3f &v : tet.vertices)
		two.vertices.push_back(v + Eigen::Vector3f(5, 0, 0));
	for (auto f : tet.faces) {
		std::swap(f[1], f[2]);
		two.faces.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
	}
	std::swap(two.faces[6][1], two.faces[6][2]);
	ASSERT_FALSE(isClosedOutward(two));
	EXPECT_TRUE(orientClosedOutward(two));
	EXPECT_TRUE(isClosedOutward(two));

	// Two shells touching along an edge (the simplified can has such a
	// pinch): that edge's four faces tie no winding, the rest still turns.
	Mesh pinch = tet;
	pinch.vertices.push_back({0, -1, 0}); // the tetrahedron turned half round the x axis
	pinch.vertices.push_back({0, 0, -1});
	for (auto f : tet.faces) {
		for (uint32_t &i : f)
			i = i == 2 ? 4 : i == 3 ? 5 : i;
		pinch.faces.push_back(f);
	}
	EXPECT_TRUE(isClosedOutward(pinch));
	std::swap(pinch.faces[7][1], pinch.faces[7][2]);
	ASSERT_FALSE(isClosedOutward(pinch));
	EXPECT_TRUE(orientClosedOutward(pinch));

	Mesh open = tet;
	open.faces.pop_back();
	EXPECT_FALSE(orientClosedOutward(open));
	Mesh fin = tet; // an edge of three faces
	fin.vertices.push_back({1, 1, 1});
	fin.faces.push_back({0, 1, 4});
	EXPECT_FALSE(orientClosedOutward(fin));

	auto can = loadPly(test::lmoDir() / "models" / "obj_000005.ply");
	ASSERT_TRUE(can.ok());
	EXPECT_FALSE(isClosedOutward(*can));
	EXPECT_TRUE(orientClosedOutward(*can));
}

} // namespace
} // namespace ihf
