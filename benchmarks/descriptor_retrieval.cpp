// SPDX-License-Identifier: MIT
// How well does a part descriptor identify the view it came from? Builds
// training parts from one set of views and query parts from another (both
// with the training pipeline), and reports how often the nearest training
// descriptor (L2) has a rotation within 20 / 45 deg of the query's and an
// offset within 0.1 diameter. With --forest, also the share of a forest's
// votes within 20 deg for the same queries. BENCHMARKS.md (issue 3) uses it
// to predict the forest's vote quality before growing forests.
//
//   descriptor_retrieval MESH.ply [--side S] [--n N] [--nr R --ntheta T --nphi P]
//                        [--weighting count|abs_weight|sign_split] [--forest F.ihf]

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
	std::fprintf(stderr, "usage: descriptor_retrieval MESH.ply [--side S] [--n N] [--nr R] [--ntheta T] "
			     "[--nphi P] [--rmin F] [--weighting count|abs_weight|sign_split] [--forest F.ihf]\n");
	return 2;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc < 2)
		return usage();
	ModelParams p;
	std::string forestFile;
	for (int i = 2; i + 1 < argc; i += 2) {
		const char *k = argv[i], *v = argv[i + 1];
		if (!std::strcmp(k, "--side"))
			p.parts.variableSide = std::strtof(v, nullptr);
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
	train.views.viewpoints = 80;
	train.views.inplaneSteps = 12;
	train.views.minDistance = 750;
	train.views.maxDistance = 850;
	train.scales = {1.0f};
	train.partsPerImage = 6;
	TrainingSetConfig query = train;
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

	if (!forestFile.empty()) {
		auto model = loadModelFile(forestFile);
		if (!model) {
			std::fprintf(stderr, "descriptor_retrieval: %s\n", model.error().message.c_str());
			return 1;
		}
		const ModelParams &fp = (*model)->params();
		std::vector<CastVote> votes(4096);
		std::vector<float> hist((*model)->forest().dims);
		double share = 0;
		for (size_t q = 0; q < m; ++q) {
			const size_t k = castPartVotes((*model)->forest(), te->cps(q), Eigen::Vector3f::Zero(), fp.hocp,
						       fp.depthCheckMarginMm, hist, votes, 0);
			double all = 0, near = 0;
			for (size_t i = 0; i < k; ++i) {
				all += votes[i].weight;
				near += angleDeg(te->labels[q].rotation, votes[i].rotation) < 20 ? votes[i].weight : 0;
			}
			share += all > 0 ? near / all : 0;
		}
		std::printf("forest %s: share of vote weight within 20 deg %.4f\n", forestFile.c_str(), share / m);
	}
	return 0;
}
