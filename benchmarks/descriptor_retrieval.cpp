// SPDX-License-Identifier: MIT
// How well does a part descriptor identify the view it came from? Builds
// training parts from one set of views and query parts from another (both
// with the training pipeline), and reports how often the nearest training
// descriptor (L2) has a rotation within 20 / 45 deg of the query's and an
// offset within 0.1 diameter, and the share of the k nearest within 20 deg.
// With --grow, a forest is grown on the training parts in process (a fast
// loop over the trainer's settings); with --forest, a forest file is walked;
// both report the share of their votes within 20 deg for the same queries.
// BENCHMARKS.md uses it to predict the forest's vote quality
// before growing full forests.
//
//   descriptor_retrieval MESH.ply [--kind fixed|variable] [--side S] [--n N]
//                        [--nr R --ntheta T --nphi P] [--rmin F]
//                        [--weighting count|abs_weight|sign_split]
//                        [--train-viewpoints V] [--train-parts P]
//                        [--grow alternate|offset|pose|sum [--templates T] [--leaf L]]
//                        [--forest F.ihf]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/estimation/forest_walker.h"
#include "core/features/hocp.h"
#include "core/geometry/mesh.h"
#include "core/geometry/ply_loader.h"
#include "core/model/forest_file.h"
#include "core/training/hocp_split_metric.h"
#include "core/training/training_set.h"

using namespace ihf;

namespace {

const CameraIntrinsics kKinect{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};

float angleDeg(const Eigen::Quaternionf &a, const Eigen::Quaternionf &b)
{
	return 2.0f * std::acos(std::min(1.0f, std::abs(a.dot(b)))) * 180.0f / static_cast<float>(M_PI);
}

int usage()
{
	std::fprintf(stderr, "usage: descriptor_retrieval MESH.ply [--kind fixed|variable] [--side S] [--n N] "
			     "[--nr R] [--ntheta T] [--nphi P] [--rmin F] [--weighting count|abs_weight|sign_split] "
			     "[--train-viewpoints V] [--train-parts P] [--grow alternate|offset|pose|sum] "
			     "[--templates T] [--leaf L] [--forest F.ihf]\n");
	return 2;
}

// Share of vote weight within 20 deg of each query's rotation, averaged
// over the queries; votesOf(q, add) calls add(rotation, weight).
template<typename VotesOf>
double nearShare(const TrainingSet &queries, VotesOf votesOf)
{
	double share = 0;
	const size_t m = queries.labels.size();
	for (size_t q = 0; q < m; ++q) {
		double all = 0, near = 0;
		votesOf(q, [&](const Eigen::Quaternionf &r, double w) {
			all += w;
			near += angleDeg(queries.labels[q].rotation, r) < 20 ? w : 0;
		});
		share += all > 0 ? near / all : 0;
	}
	return m ? share / static_cast<double>(m) : 0;
}

// Walks an in-memory tree with the same depth-checked test as the forest
// file's walker; returns the leaf.
const TreeNode &leafOf(const HoughTree &t, std::span<const PartCp> cps, int dims, const ModelParams &p,
		       std::span<float> h)
{
	int32_t ni = 0;
	while (!t.nodes[ni].isLeaf()) {
		const TreeNode &nd = t.nodes[ni];
		computeHocpDepthChecked(cps, nd.zMin, nd.zMax, p.depthCheckMarginMm, p.hocp, h);
		const auto templ = std::span<const float>(t.templates).subspan(size_t(nd.templateIndex) * dims, dims);
		ni = std::sqrt(hocpDistanceSquared(h, templ)) < nd.threshold ? nd.left : nd.right;
	}
	return t.nodes[ni];
}

} // namespace

int main(int argc, char **argv)
{
	if (argc < 2)
		return usage();
	ModelParams p;
	std::string forestFile;
	int trainViewpoints = 80, trainParts = 6;
	bool grow = false;
	ForestTrainerConfig fc;
	for (int i = 2; i + 1 < argc; i += 2) {
		const char *k = argv[i], *v = argv[i + 1];
		if (!std::strcmp(k, "--side"))
			p.parts.variableSide = std::strtof(v, nullptr);
		else if (!std::strcmp(k, "--kind"))
			p.parts.kind = !std::strcmp(v, "fixed") ? PartKind::kFixed : PartKind::kVariable;
		else if (!std::strcmp(k, "--train-viewpoints"))
			trainViewpoints = std::atoi(v);
		else if (!std::strcmp(k, "--train-parts"))
			trainParts = std::atoi(v);
		else if (!std::strcmp(k, "--grow")) {
			grow = true;
			fc.objective = !std::strcmp(v, "offset") ? SplitObjective::kOffset
				       : !std::strcmp(v, "pose") ? SplitObjective::kPose
				       : !std::strcmp(v, "sum")  ? SplitObjective::kSum
								 : SplitObjective::kAlternate;
		} else if (!std::strcmp(k, "--templates"))
			fc.templatesPerNode = std::atoi(v);
		else if (!std::strcmp(k, "--leaf"))
			fc.maxLeafSamples = std::atoi(v);
		else if (!std::strcmp(k, "--n"))
			p.ibs.n = std::atoi(v);
		else if (!std::strcmp(k, "--nr"))
			p.hocp.nR = std::atoi(v);
		else if (!std::strcmp(k, "--ntheta"))
			p.hocp.nTheta = std::atoi(v);
		else if (!std::strcmp(k, "--nphi"))
			p.hocp.nPhi = std::atoi(v);
		else if (!std::strcmp(k, "--rmin"))
			p.hocp.rMinFraction = std::strtof(v, nullptr);
		else if (!std::strcmp(k, "--weighting"))
			p.hocp.weighting = !std::strcmp(v, "abs_weight") ? HocpWeighting::kAbsWeight
					   : !std::strcmp(v, "sign_split") ? HocpWeighting::kSignSplit
									  : HocpWeighting::kCount;
		else if (!std::strcmp(k, "--forest"))
			forestFile = v;
		else
			return usage();
	}
	auto mesh = loadPly(argv[1]);
	if (!mesh) {
		std::fprintf(stderr, "descriptor_retrieval: %s\n", mesh.error().message.c_str());
		return 1;
	}
	p.diameter = meshDiameter(*mesh);

	TrainingSetConfig train;
	train.views.viewpoints = trainViewpoints;
	train.views.inplaneSteps = 12;
	train.views.minDistance = 750;
	train.views.maxDistance = 850;
	train.scales = {1.0f};
	train.partsPerImage = trainParts;
	TrainingSetConfig query = train;
	query.partsPerImage = 6;
	query.views.viewpoints = 10;
	query.views.seed = 7;
	query.seed = 9;
	auto tr = buildTrainingSet(*mesh, kKinect, p, train);
	auto te = buildTrainingSet(*mesh, kKinect, p, query);
	if (!tr || !te) {
		std::fprintf(stderr, "descriptor_retrieval: %s\n", (!tr ? tr.error() : te.error()).message.c_str());
		return 1;
	}
	const size_t n = tr->labels.size(), m = te->labels.size();
	int rot20 = 0, rot45 = 0, offsetOk = 0;
	for (size_t q = 0; q < m; ++q) {
		const auto hq = te->histogram(q);
		float best = INFINITY;
		size_t bi = 0;
		for (size_t i = 0; i < n; ++i) {
			const float d = hocpDistanceSquared(hq, tr->histogram(i));
			if (d < best)
				best = d, bi = i;
		}
		const float a = angleDeg(te->labels[q].rotation, tr->labels[bi].rotation);
		rot20 += a < 20;
		rot45 += a < 45;
		offsetOk += (te->labels[q].offset - tr->labels[bi].offset).norm() < 0.1 * p.diameter;
	}
	std::printf("dims %d, %zu training parts, %zu queries: nearest within 20 deg %.3f, within 45 deg %.3f, "
		    "offset within 0.1 d %.3f\n",
		    tr->dims, n, m, double(rot20) / m, double(rot45) / m, double(offsetOk) / m);

	// The k nearest: what a leaf of k similar parts could hold at best.
	{
		const size_t kMax = std::min<size_t>(45, n);
		std::vector<std::pair<float, uint32_t>> d(n);
		std::printf("k nearest, share within 20 deg:");
		for (size_t k : {size_t(1), size_t(5), size_t(15), size_t(45)}) {
			if (k > kMax)
				break;
			const double share = nearShare(*te, [&](size_t q, auto add) {
				for (size_t i = 0; i < n; ++i)
					d[i] = {hocpDistanceSquared(te->histogram(q), tr->histogram(i)), uint32_t(i)};
				std::partial_sort(d.begin(), d.begin() + k, d.end());
				for (size_t i = 0; i < k; ++i)
					add(tr->labels[d[i].second].rotation, 1.0);
			});
			std::printf(" k=%zu %.4f", k, share);
		}
		std::printf("\n");
	}

	if (grow) {
		fc.threads = 2;
		HocpSplitMetric metric(*tr, p.hocp, p.depthCheckMarginMm);
		const HoughForest forest = trainForest(fc, metric, tr->labels);
		std::vector<float> h(tr->dims);
		double leafVotes = 0;
		const double share = nearShare(*te, [&](size_t q, auto add) {
			for (const HoughTree &t : forest.trees) {
				const TreeNode &leaf = leafOf(t, te->cps(q), tr->dims, p, h);
				leafVotes += leaf.voteCount;
				for (uint32_t i = 0; i < leaf.voteCount; ++i)
					add(t.votes[leaf.voteBegin + i].rotation, 1.0);
			}
		});
		std::printf("grown forest (%d templates per node, leaf %d): %zu nodes, %.1f votes per leaf reached, "
			    "share of votes within 20 deg %.4f\n",
			    fc.templatesPerNode, fc.maxLeafSamples, forest.nodeCount(),
			    leafVotes / double(m * forest.trees.size()), share);
	}

	if (!forestFile.empty()) {
		auto model = loadModelFile(forestFile);
		if (!model) {
			std::fprintf(stderr, "descriptor_retrieval: %s\n", model.error().message.c_str());
			return 1;
		}
		const ModelParams &fp = (*model)->params();
		std::vector<CastVote> votes(4096);
		std::vector<float> hist((*model)->forest().dims);
		const double share = nearShare(*te, [&](size_t q, auto add) {
			const size_t k = castPartVotes((*model)->forest(), te->cps(q), Eigen::Vector3f::Zero(), fp.hocp,
						       fp.depthCheckMarginMm, hist, votes, 0);
			for (size_t i = 0; i < k; ++i)
				add(votes[i].rotation, votes[i].weight);
		});
		std::printf("forest %s: share of vote weight within 20 deg %.4f\n", forestFile.c_str(), share);
	}
	return 0;
}
