// SPDX-License-Identifier: MIT
// The threads of a box's searches (EstimatorLimits::threads) change how fast
// a box is done, never its pose: the view search, the vote modes and the
// forest walk give the bits of one thread for any number of threads, also
// when the vote buffer fills up (the forest walk's shares then overflow and
// one thread walks again), and the half-turns' screen does too.

#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/pose_estimator.h"
#include "core/training/view_template_builder.h"
#include "tests/common/sanitizers.h"
#include "tests/runtime/small_model.h"

namespace ihf {
namespace {

// The thread counts compared with one thread: two, and three (shares that
// do not divide evenly). Under AddressSanitizer, which makes each estimate
// ~7x slower, three alone: its shares take every path that two take.
#ifdef IHF_TEST_ASAN
constexpr int kThreadCounts[] = {3};
#else
constexpr int kThreadCounts[] = {2, 3};
#endif

struct Box {
	PixelBox box;
	bool real;
};

TEST(EstimatorThreads, PosesDoNotDependOnTheThreadCount)
{
	test::SmallModel duck = test::trainSmallModel(9, 5);
	ASSERT_TRUE(duck.model);
	auto pts = buildViewTemplatePoints(duck.model->mesh(), duck.model->params().diameter, {60, 64});
	ASSERT_TRUE(pts.ok());
	duck.model->attachViewTemplates(60, 64, std::move(*pts));

	// A clean synthetic frame with two ducks (one box each, and one box
	// over both) and a noisy copy of it.
	DepthImageMm clean(640, 480, 0.0f);
	const PixelBox a = test::renderInto(*duck.model, test::viewAt(duck, 11, {-80, 20, 790}), clean);
	const PixelBox b = test::renderInto(*duck.model, test::viewAt(duck, 47, {90, -30, 830}), clean);
	DepthImageMm noisy(640, 480, 0.0f);
	for (int y = 0; y < 480; ++y)
		for (int x = 0; x < 640; ++x)
			if (clean.at(x, y) > 0 && (x * 7 + y * 13) % 11 != 0)
				noisy.at(x, y) = clean.at(x, y) + static_cast<float>((x * 31 + y * 17) % 9) - 4.0f;
	const PixelBox both{a.x, std::min(a.y, b.y), b.x + b.w - a.x, std::max(a.y + a.h, b.y + b.h) - std::min(a.y, b.y)};

	EstimatorConfig cfg;
	cfg.iterations = 2;
	cfg.icp = true;
	cfg.icpCandidates = 4;
	cfg.views.inplane = 12;
	cfg.views.coarseKeep = 200;
	cfg.views.depthCentres = 1;
	cfg.halfTurns = HalfTurnConfig{1, 8, 1};

	auto estimateAll = [&](int threads, int maxVotes) {
		EstimatorLimits limits;
		limits.maxMeshVertices = duck.model->mesh().vertices.size();
		limits.threads = threads;
		limits.maxVotes = maxVotes;
		PoseEstimator estimator(limits);
		EXPECT_TRUE(estimator.valid());
		std::vector<PoseEstimate> out;
		for (const DepthImageMm *frame : {&clean, &noisy})
			for (const PixelBox &box : {a, b, both})
				out.push_back(estimator.estimate(frame->view(), test::kKinect, box, *duck.model, cfg));
		return out;
	};
	// The half-turns rendered (screen 0), then screened on the templates.
	for (const auto &[maxVotes, screen] : {std::pair{144000, 0}, std::pair{1500, 0}, std::pair{144000, 3}}) {
		cfg.halfTurns.screen = screen;
		const std::vector<PoseEstimate> one = estimateAll(1, maxVotes);
		int found = 0;
		for (const PoseEstimate &e : one)
			found += e.found;
		EXPECT_GE(found, 4) << "max votes " << maxVotes << ", screen " << screen;
		for (int threads : kThreadCounts) {
			const std::vector<PoseEstimate> many = estimateAll(threads, maxVotes);
			ASSERT_EQ(many.size(), one.size());
			for (size_t i = 0; i < one.size(); ++i) {
				SCOPED_TRACE(testing::Message() << "box " << i << ", " << threads << " threads, max votes " << maxVotes
								<< ", screen " << screen);
				EXPECT_EQ(many[i].found, one[i].found);
				EXPECT_TRUE(many[i].pose.R == one[i].pose.R);
				EXPECT_TRUE(many[i].pose.t == one[i].pose.t);
				EXPECT_EQ(many[i].score.score, one[i].score.score);
				EXPECT_EQ(many[i].votes, one[i].votes);
				EXPECT_EQ(many[i].iterationsDone, one[i].iterationsDone);
			}
		}
	}
}

} // namespace
} // namespace ihf
