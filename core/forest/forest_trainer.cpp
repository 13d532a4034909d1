// SPDX-License-Identifier: MIT
#include "core/forest/forest_trainer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <thread>

#include <Eigen/Dense>

namespace ihf {

namespace {

// Gaussian entropy up to constants: 0.5 log det(cov + lambda I), from sums.
template<int D>
struct Moments {
	Eigen::Matrix<double, D, 1> s1 = Eigen::Matrix<double, D, 1>::Zero();
	Eigen::Matrix<double, D, D> s2 = Eigen::Matrix<double, D, D>::Zero();

	void add(const Eigen::Matrix<double, D, 1> &x)
	{
		s1 += x;
		s2.noalias() += x * x.transpose();
	}
	double entropy(double n, double lambda) const
	{
		if (n < 1)
			return 0;
		Eigen::Matrix<double, D, 1> m = s1 / n;
		Eigen::Matrix<double, D, D> c = s2 / n - m * m.transpose();
		c.diagonal().array() += lambda;
		return 0.5 * std::log(std::max(c.determinant(), 1e-300));
	}
};

struct Candidate {
	uint32_t templ = 0;
	float threshold = 0;
	double cost = std::numeric_limits<double>::infinity();
	size_t leftCount = 0;
};

class TreeGrower
{
public:
	TreeGrower(const ForestTrainerConfig &cfg, const SplitMetric &metric,
		   std::span<const Vote> labels, uint64_t seed, std::atomic<size_t> &done,
		   size_t total, const TrainProgress &progress)
		: cfg_(cfg), metric_(metric), labels_(labels), rng_(seed), done_(done),
		  total_(total), progress_(progress)
	{
	}

	HoughTree grow(std::vector<uint32_t> samples)
	{
		tree_ = HoughTree{};
		samples_ = std::move(samples);
		tree_.nodes.emplace_back();
		struct Job {
			int32_t node;
			size_t begin, end;
			int depth;
		};
		std::vector<Job> stack{{0, 0, samples_.size(), 1}};
		while (!stack.empty()) {
			Job job = stack.back();
			stack.pop_back();
			size_t n = job.end - job.begin;
			Candidate best;
			bool split = job.depth < cfg_.maxDepth &&
				     n > static_cast<size_t>(cfg_.maxLeafSamples) &&
				     findSplit(job.begin, job.end, best);
			if (!split) {
				makeLeaf(job.node, job.begin, job.end);
				continue;
			}
			size_t mid = partition(job.begin, job.end, best);
			TreeNode &node = tree_.nodes[job.node];
			node.templateIndex = static_cast<uint32_t>(tree_.templates.size() / metric_.dims());
			node.threshold = best.threshold;
			tree_.templates.resize(tree_.templates.size() + metric_.dims());
			metric_.templateOf(best.templ,
					   std::span<float>(tree_.templates).last(metric_.dims()),
					   node.zMin, node.zMax);
			int32_t left = static_cast<int32_t>(tree_.nodes.size());
			tree_.nodes[job.node].left = left;
			tree_.nodes[job.node].right = left + 1;
			tree_.nodes.emplace_back();
			tree_.nodes.emplace_back();
			stack.push_back({left + 1, mid, job.end, job.depth + 1});
			stack.push_back({left, job.begin, mid, job.depth + 1});
		}
		return std::move(tree_);
	}

private:
	bool findSplit(size_t begin, size_t end, Candidate &best)
	{
		const size_t n = end - begin;
		std::span<const uint32_t> node(samples_.data() + begin, n);

		SplitObjective objective = cfg_.objective;
		if (objective == SplitObjective::kAlternate)
			objective = (rng_() & 1) ? SplitObjective::kOffset : SplitObjective::kPose;

		// Rotation labels are aligned to one hemisphere per node so that
		// q and -q do not inflate the covariance.
		Eigen::Vector4f ref = labels_[node[0]].rotation.coeffs();

		std::vector<uint32_t> templ(cfg_.templatesPerNode);
		for (auto &t : templ)
			t = node[rng_() % n];

		std::vector<Candidate> results(templ.size());
		auto evaluate = [&](size_t c, std::vector<float> &dist, std::vector<uint32_t> &order) {
			dist.resize(n);
			order.resize(n);
			metric_.distances(templ[c], node, dist);
			std::iota(order.begin(), order.end(), 0u);
			std::sort(order.begin(), order.end(),
				  [&](uint32_t a, uint32_t b) { return dist[a] < dist[b]; });
			results[c] = bestThreshold(node, dist, order, objective, ref);
			results[c].templ = templ[c];
		};

		const int threads = std::max(1, cfg_.threads);
		if (threads == 1 || n < 2000) {
			std::vector<float> dist;
			std::vector<uint32_t> order;
			for (size_t c = 0; c < templ.size(); ++c)
				evaluate(c, dist, order);
		} else {
			std::atomic<size_t> next{0};
			std::vector<std::thread> pool;
			for (int t = 0; t < threads; ++t)
				pool.emplace_back([&] {
					std::vector<float> dist;
					std::vector<uint32_t> order;
					for (size_t c; (c = next++) < templ.size();)
						evaluate(c, dist, order);
				});
			for (auto &th : pool)
				th.join();
		}

		// Parent entropy: a split must reduce it.
		double parent = costOf(node, objective, ref);
		for (const auto &r : results)
			if (r.cost < best.cost)
				best = r;
		return best.leftCount > 0 && best.leftCount < n && best.cost < parent - 1e-9;
	}

	double costOf(std::span<const uint32_t> node, SplitObjective objective,
		      const Eigen::Vector4f &ref) const
	{
		Moments<3> mo;
		Moments<4> mr;
		for (uint32_t s : node) {
			mo.add(labels_[s].offset.cast<double>());
			mr.add(aligned(labels_[s].rotation, ref));
		}
		return weightedCost(mo, mr, static_cast<double>(node.size()), objective);
	}

	double weightedCost(const Moments<3> &mo, const Moments<4> &mr, double n,
			    SplitObjective objective) const
	{
		double c = 0;
		if (objective != SplitObjective::kPose)
			c += n * mo.entropy(n, cfg_.offsetRegulariser);
		if (objective != SplitObjective::kOffset)
			c += n * mr.entropy(n, cfg_.rotationRegulariser);
		return c;
	}

	static Eigen::Vector4d aligned(const Eigen::Quaternionf &q, const Eigen::Vector4f &ref)
	{
		Eigen::Vector4f c = q.coeffs();
		if (c.dot(ref) < 0)
			c = -c;
		return c.cast<double>();
	}

	// Sweeps every distinct threshold of the sorted distances with prefix
	// moments: O(n) after the sort.
	Candidate bestThreshold(std::span<const uint32_t> node, const std::vector<float> &dist,
				const std::vector<uint32_t> &order, SplitObjective objective,
				const Eigen::Vector4f &ref) const
	{
		const size_t n = node.size();
		Moments<3> totalO, leftO;
		Moments<4> totalR, leftR;
		for (uint32_t s : node) {
			totalO.add(labels_[s].offset.cast<double>());
			totalR.add(aligned(labels_[s].rotation, ref));
		}
		Candidate best;
		for (size_t k = 1; k < n; ++k) {
			uint32_t s = node[order[k - 1]];
			leftO.add(labels_[s].offset.cast<double>());
			leftR.add(aligned(labels_[s].rotation, ref));
			if (dist[order[k]] <= dist[order[k - 1]])
				continue; // not a valid cut between equal distances
			Moments<3> rightO{totalO.s1 - leftO.s1, totalO.s2 - leftO.s2};
			Moments<4> rightR{totalR.s1 - leftR.s1, totalR.s2 - leftR.s2};
			double cost = weightedCost(leftO, leftR, static_cast<double>(k), objective) +
				      weightedCost(rightO, rightR, static_cast<double>(n - k), objective);
			if (cost < best.cost) {
				best.cost = cost;
				best.threshold = 0.5f * (dist[order[k - 1]] + dist[order[k]]);
				best.leftCount = k;
			}
		}
		return best;
	}

	size_t partition(size_t begin, size_t end, const Candidate &c)
	{
		std::span<const uint32_t> node(samples_.data() + begin, end - begin);
		std::vector<float> dist(node.size());
		metric_.distances(c.templ, node, dist);
		std::vector<uint32_t> left, right;
		for (size_t i = 0; i < node.size(); ++i)
			(dist[i] < c.threshold ? left : right).push_back(node[i]);
		std::copy(left.begin(), left.end(), samples_.begin() + begin);
		std::copy(right.begin(), right.end(), samples_.begin() + begin + left.size());
		return begin + left.size();
	}

	void makeLeaf(int32_t nodeIndex, size_t begin, size_t end)
	{
		TreeNode &node = tree_.nodes[nodeIndex];
		node.left = node.right = -1;
		node.voteBegin = static_cast<uint32_t>(tree_.votes.size());
		node.voteCount = static_cast<uint32_t>(end - begin);
		for (size_t i = begin; i < end; ++i)
			tree_.votes.push_back(labels_[samples_[i]]);
		size_t d = done_ += end - begin;
		if (progress_)
			progress_(d, total_);
	}

	const ForestTrainerConfig &cfg_;
	const SplitMetric &metric_;
	std::span<const Vote> labels_;
	std::mt19937_64 rng_;
	std::atomic<size_t> &done_;
	size_t total_;
	const TrainProgress &progress_;
	HoughTree tree_;
	std::vector<uint32_t> samples_;
};

} // namespace

HoughForest trainForest(const ForestTrainerConfig &config, const SplitMetric &metric,
			std::span<const Vote> labels, const TrainProgress &progress)
{
	HoughForest forest;
	forest.dims = metric.dims();
	const size_t all = labels.size();
	const size_t perTree = std::max<size_t>(
		1, static_cast<size_t>(std::lround(config.sampleFraction * static_cast<double>(all))));
	std::atomic<size_t> done{0};
	const size_t total = perTree * static_cast<size_t>(config.trees);

	for (int t = 0; t < config.trees; ++t) {
		// Each tree has its own stream, so results do not depend on threads.
		uint64_t seed = config.seed * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(t) + 1;
		std::mt19937_64 rng(seed);
		std::vector<uint32_t> samples(all);
		std::iota(samples.begin(), samples.end(), 0u);
		// Partial Fisher-Yates with our own index draws: reproducible
		// everywhere (std::shuffle's algorithm is not specified).
		for (size_t i = 0; i < perTree && i + 1 < all; ++i)
			std::swap(samples[i], samples[i + rng() % (all - i)]);
		samples.resize(perTree);
		std::sort(samples.begin(), samples.end());
		TreeGrower grower(config, metric, labels, rng(), done, total, progress);
		forest.trees.push_back(grower.grow(std::move(samples)));
	}
	return forest;
}

} // namespace ihf
