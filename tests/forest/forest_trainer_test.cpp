// SPDX-License-Identifier: MIT
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/forest/forest_trainer.h"

namespace ihf {
namespace {

// A 2-D feature per sample; the "histogram" is the feature itself and the
// depth check is the identity. Labels depend on which quadrant a sample is
// in, so a good forest must route samples by quadrant.
class PointMetric : public SplitMetric
{
public:
	explicit PointMetric(std::vector<Eigen::Vector2f> f) : f_(std::move(f)) {}
	int dims() const override { return 2; }
	void distances(uint32_t t, std::span<const uint32_t> s, std::span<float> out) const override
	{
		for (size_t i = 0; i < s.size(); ++i)
			out[i] = (f_[s[i]] - f_[t]).norm();
	}
	void templateOf(uint32_t t, std::span<float> h, float &zMin, float &zMax) const override
	{
		h[0] = f_[t].x();
		h[1] = f_[t].y();
		zMin = -1;
		zMax = 1;
	}

private:
	std::vector<Eigen::Vector2f> f_;
};

struct Data {
	std::vector<Eigen::Vector2f> features;
	std::vector<Vote> labels;
};

Data makeData(int n, uint64_t seed)
{
	std::mt19937_64 rng(seed);
	std::uniform_real_distribution<float> u(-1, 1);
	Data d;
	for (int i = 0; i < n; ++i) {
		Eigen::Vector2f f(u(rng), u(rng));
		int quadrant = (f.x() > 0) + 2 * (f.y() > 0);
		Vote v;
		v.offset = Eigen::Vector3f(100.0f * quadrant, 0, 0);
		v.rotation = Eigen::Quaternionf(Eigen::AngleAxisf(0.5f * quadrant, Eigen::Vector3f::UnitZ()));
		d.features.push_back(f);
		d.labels.push_back(v);
	}
	return d;
}

// Walks one tree with a feature and returns the leaf.
const TreeNode &leafOf(const HoughTree &t, const Eigen::Vector2f &f)
{
	int32_t n = 0;
	while (!t.nodes[n].isLeaf()) {
		const float *h = &t.templates[2 * t.nodes[n].templateIndex];
		float d = (f - Eigen::Vector2f(h[0], h[1])).norm();
		n = d < t.nodes[n].threshold ? t.nodes[n].left : t.nodes[n].right;
	}
	return t.nodes[n];
}

TEST(ForestTrainer, LeavesArePureWhereLabelsAreSeparable)
{
	Data d = makeData(3000, 7);
	PointMetric metric(d.features);
	ForestTrainerConfig cfg;
	cfg.maxLeafSamples = 15;
	cfg.seed = 3;
	HoughForest forest = trainForest(cfg, metric, d.labels);
	ASSERT_EQ(forest.trees.size(), 3u);

	// Test points away from the quadrant borders: their leaves' votes
	// should mostly carry the right quadrant's offset.
	std::mt19937_64 rng(99);
	std::uniform_real_distribution<float> u(0.15f, 0.95f);
	int correct = 0, total = 0;
	for (int i = 0; i < 200; ++i) {
		Eigen::Vector2f f(u(rng) * (i & 1 ? 1 : -1), u(rng) * (i & 2 ? 1 : -1));
		int quadrant = (f.x() > 0) + 2 * (f.y() > 0);
		for (const auto &tree : forest.trees) {
			const TreeNode &leaf = leafOf(tree, f);
			for (uint32_t v = 0; v < leaf.voteCount; ++v) {
				correct += std::abs(tree.votes[leaf.voteBegin + v].offset.x() - 100.0f * quadrant) < 1;
				total++;
			}
		}
	}
	EXPECT_GT(static_cast<double>(correct) / total, 0.9);
	for (const auto &tree : forest.trees) {
		EXPECT_LE(tree.depth(), cfg.maxDepth);
		for (const auto &n : tree.nodes) {
			if (n.isLeaf()) {
				EXPECT_GE(n.voteCount, 1u);
			}
		}
	}
}

TEST(ForestTrainer, DeterministicFromSeedAndThreadCount)
{
	Data d = makeData(2500, 11);
	PointMetric metric(d.features);
	ForestTrainerConfig cfg;
	cfg.seed = 5;
	cfg.threads = 1;
	HoughForest a = trainForest(cfg, metric, d.labels);
	cfg.threads = 2;
	HoughForest b = trainForest(cfg, metric, d.labels);
	cfg.seed = 6;
	HoughForest c = trainForest(cfg, metric, d.labels);
	ASSERT_EQ(a.trees.size(), b.trees.size());
	for (size_t t = 0; t < a.trees.size(); ++t) {
		ASSERT_EQ(a.trees[t].nodes.size(), b.trees[t].nodes.size());
		EXPECT_EQ(a.trees[t].templates, b.trees[t].templates);
		for (size_t n = 0; n < a.trees[t].nodes.size(); ++n)
			EXPECT_EQ(a.trees[t].nodes[n].threshold, b.trees[t].nodes[n].threshold);
	}
	bool differs = a.trees[0].nodes.size() != c.trees[0].nodes.size() ||
		       a.trees[0].templates != c.trees[0].templates;
	EXPECT_TRUE(differs);
}

TEST(ForestTrainer, RespectsDepthAndLeafSize)
{
	Data d = makeData(1000, 13);
	PointMetric metric(d.features);
	ForestTrainerConfig cfg;
	cfg.maxDepth = 4;
	cfg.trees = 1;
	cfg.sampleFraction = 1.0f;
	HoughForest f = trainForest(cfg, metric, d.labels);
	EXPECT_LE(f.trees[0].depth(), 4);
	EXPECT_EQ(f.trees[0].votes.size(), 1000u); // every sample lands in a leaf
}

} // namespace
} // namespace ihf
