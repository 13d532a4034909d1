// SPDX-License-Identifier: MIT
// The forest walk reuses a node's depth-checked histogram when the next
// node keeps the same control points: the votes must be exactly those of
// recomputing it at every node.

#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/forest_walker.h"
#include "tests/runtime/small_model.h"

namespace ihf {
namespace {

TEST(ForestWalker, ReusedHistogramsCastTheVeryVotesOfRecomputedOnes)
{
	auto mesh = loadPly(test::lmoDir() / "models" / "obj_000009.ply");
	ASSERT_TRUE(mesh.ok());
	ModelParams params;
	params.objId = 9;
	params.diameter = meshDiameter(*mesh);
	TrainingSetConfig set;
	set.views.viewpoints = 20;
	set.views.inplaneSteps = 3;
	set.views.minDistance = 750;
	set.views.maxDistance = 850;
	set.scales = {1.0f, 1.5f};
	set.partsPerImage = 10;
	auto training = buildTrainingSet(*mesh, test::kKinect, params, set);
	ASSERT_TRUE(training.ok());
	HocpSplitMetric metric(*training, params.hocp, params.depthCheckMarginMm);
	ForestTrainerConfig fc;
	fc.seed = 3;
	const OwnedObjectModel model(params, std::move(*mesh),
				     ForestStorage(trainForest(fc, metric, training->labels), TemplateEncoding::kUint8));
	const ForestView &forest = model.forest();
	const size_t dims = static_cast<size_t>(forest.dims);

	std::vector<float> one(dims), two(2 * dims);
	std::vector<CastVote> a(64 * 1024), b(64 * 1024);
	size_t na = 0, nb = 0;
	for (size_t i = 0; i < training->samples.size(); ++i) {
		const Eigen::Vector3f centre(static_cast<float>(i), 0, 800);
		na = castPartVotes(forest, training->cps(i), centre, params.hocp, params.depthCheckMarginMm, one, a, na);
		nb = castPartVotes(forest, training->cps(i), centre, params.hocp, params.depthCheckMarginMm, two, b, nb);
	}
	ASSERT_GT(na, 1000u);
	ASSERT_EQ(na, nb);
	for (size_t i = 0; i < na; ++i) {
		ASSERT_EQ(a[i].centre, b[i].centre) << i;
		ASSERT_EQ(a[i].rotation.coeffs(), b[i].rotation.coeffs()) << i;
		ASSERT_EQ(a[i].weight, b[i].weight) << i;
	}
}

} // namespace
} // namespace ihf
