// SPDX-License-Identifier: MIT
// The forest walk reuses a node's depth-checked histogram when a later
// node keeps the same control points: the votes must be exactly those of
// recomputing it at every node, whatever the number of histograms kept.

#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/forest_walker.h"
#include "tests/runtime/small_model.h"

namespace ihf {
namespace {

TEST(ForestWalker, ReusedHistogramsCastTheVeryVotesOfRecomputedOnes)
{
	const test::SmallModel m = test::trainSmallModel(9, 3);
	ASSERT_TRUE(m.model && m.training);
	const TrainingSet &training = *m.training;
	const ModelParams &params = m.model->params();
	const ForestView &forest = m.model->forest();
	const size_t dims = static_cast<size_t>(forest.dims);

	std::vector<float> one(dims);
	std::vector<CastVote> a(64 * 1024), b(64 * 1024);
	size_t na = 0;
	for (size_t i = 0; i < training.samples.size(); ++i) {
		const Eigen::Vector3f centre(static_cast<float>(i), 0, 800);
		na = castPartVotes(forest, training.cps(i), centre, params.hocp, params.depthCheckMarginMm, one, a, na);
	}
	ASSERT_GT(na, 1000u);
	// Two slots (the all-points set and the last), a few (round robin
	// refills), and the most.
	for (size_t slots : {size_t{2}, size_t{3}, size_t{5}, kMaxHistogramSlots}) {
		std::vector<float> hist(slots * dims);
		size_t nb = 0;
		for (size_t i = 0; i < training.samples.size(); ++i) {
			const Eigen::Vector3f centre(static_cast<float>(i), 0, 800);
			nb = castPartVotes(forest, training.cps(i), centre, params.hocp, params.depthCheckMarginMm, hist, b,
					   nb);
		}
		ASSERT_EQ(na, nb) << slots << " slots";
		for (size_t i = 0; i < na; ++i) {
			ASSERT_EQ(a[i].centre, b[i].centre) << i << ", " << slots << " slots";
			ASSERT_EQ(a[i].rotation.coeffs(), b[i].rotation.coeffs()) << i << ", " << slots << " slots";
			ASSERT_EQ(a[i].weight, b[i].weight) << i << ", " << slots << " slots";
		}
	}
}

} // namespace
} // namespace ihf
