// SPDX-License-Identifier: MIT
// Mesh measures: bounding box, exact diameter (against brute force), and
// degenerate-face counting.

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

} // namespace
} // namespace ihf
