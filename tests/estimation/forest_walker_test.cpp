// SPDX-License-Identifier: MIT
// The forest walk reuses a node's depth-checked histogram when a later
// node keeps the same control points: the votes must be exactly those of
// recomputing it at every node, whatever the number of histograms kept.

#include <cmath>
#include <cstdint>
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

// The distance is summed in lanes (so that it vectorises); it must still be
// the L2 distance: checked against a double-precision sum for both
// encodings (uint8 sparse, with empty bins) and for lengths that leave a
// tail past the lanes. The sparse sum must also be the same bits as the
// dense 8-bit values it stands for, which the file used to store.
TEST(ForestWalker, TemplateDistanceIsTheL2DistanceForEveryLengthAndEncoding)
{
	for (int dims : {1, 7, 8, 13, 64, 256, 259, 520}) {
		std::vector<float> hist(static_cast<size_t>(dims)), floats(static_cast<size_t>(2 * dims));
		std::vector<uint8_t> bytes(static_cast<size_t>(2 * dims));
		for (int i = 0; i < 2 * dims; ++i) {
			// Two bins in three empty, as in a HoCP histogram.
			bytes[static_cast<size_t>(i)] = i % 3 == 0 ? static_cast<uint8_t>((i * 37 + 11) % 256) : 0;
			floats[static_cast<size_t>(i)] = static_cast<float>(bytes[static_cast<size_t>(i)]) / 255.0f;
		}
		for (int i = 0; i < dims; ++i)
			hist[static_cast<size_t>(i)] = static_cast<float>((i * 53 + 5) % 97) / 97.0f;
		std::vector<uint8_t> sparse;
		std::vector<uint32_t> offsets;
		for (size_t k = 0; k < 2; ++k) {
			offsets.push_back(static_cast<uint32_t>(sparse.size()));
			appendSparseTemplate(std::span<const uint8_t>(bytes).subspan(k * dims, dims), sparse);
		}
		EXPECT_LT(sparse.size(), bytes.size() + 2 * templateBitmapBytes(dims));
		for (TemplateEncoding encoding : {TemplateEncoding::kFloat32, TemplateEncoding::kUint8}) {
			TreeView tree;
			tree.templates = encoding == TemplateEncoding::kFloat32 ? static_cast<const void *>(floats.data())
										  : static_cast<const void *>(sparse.data());
			tree.templateOffsets = offsets;
			ForestView forest;
			forest.dims = dims;
			forest.encoding = encoding;
			forest.trees = std::span<const TreeView>(&tree, 1);
			for (uint32_t index : {0u, 1u}) {
				double ref = 0;
				for (int i = 0; i < dims; ++i) {
					const double e = hist[static_cast<size_t>(i)] -
							 floats[static_cast<size_t>(index * dims + i)];
					ref += e * e;
				}
				const float d = templateDistance(forest, tree, index, hist);
				EXPECT_NEAR(d, std::sqrt(ref), 1e-5 * std::sqrt(ref) + 1e-7)
					<< dims << " dims, template " << index;
				if (encoding == TemplateEncoding::kUint8) {
					// The dense 8-bit sum, in the walker's lane order.
					float lane[8] = {};
					int i = 0;
					for (; i + 8 <= dims; i += 8)
						for (int l = 0; l < 8; ++l) {
							const float e = hist[static_cast<size_t>(i + l)] -
									static_cast<float>(bytes[index * dims + i + l]) *
										(1.0f / 255.0f);
							lane[l] += e * e;
						}
					float acc = ((lane[0] + lane[4]) + (lane[1] + lane[5])) +
						    ((lane[2] + lane[6]) + (lane[3] + lane[7]));
					for (; i < dims; ++i) {
						const float e = hist[static_cast<size_t>(i)] -
								static_cast<float>(bytes[index * dims + i]) * (1.0f / 255.0f);
						acc += e * e;
					}
					EXPECT_EQ(d, std::sqrt(acc)) << dims << " dims, template " << index;
				}
			}
		}
	}
}

} // namespace
} // namespace ihf
