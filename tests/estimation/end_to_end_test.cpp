// SPDX-License-Identifier: MIT
// A small forest trained from a real mesh recovers a known pose on a clean
// render, end to end (training views -> parts -> forest -> file -> votes ->
// refinement); training is deterministic; bad boxes give "no pose".

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "core/eval/pose_error.h"
#include "core/estimation/pose_distance.h"
#include "core/estimation/pose_estimator.h"
#include "core/forest/forest_trainer.h"
#include "core/geometry/ply_loader.h"
#include "core/geometry/rotation.h"
#include "core/model/forest_file.h"
#include "core/render/depth_renderer.h"
#include "core/training/hocp_split_metric.h"
#include "core/training/training_set.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

const CameraIntrinsics kKinect{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};

struct Trained {
	Mesh mesh;
	ModelParams params;
	HoughForest forest;
	TrainingSetConfig set;
};

Trained trainSmall(uint64_t seed)
{
	Trained t;
	auto mesh = loadPly(test::lmoDir() / "models" / "obj_000001.ply");
	EXPECT_TRUE(mesh.ok());
	t.mesh = mesh.value();
	t.params.objId = 1;
	t.params.diameter = meshDiameter(t.mesh);
	t.set.views.viewpoints = 40;
	t.set.views.inplaneSteps = 4;
	t.set.views.minDistance = 750;
	t.set.views.maxDistance = 850;
	t.set.views.seed = seed;
	t.set.scales = {1.0f};
	t.set.partsPerImage = 20;
	t.set.seed = seed;
	auto set = buildTrainingSet(t.mesh, kKinect, t.params, t.set);
	EXPECT_TRUE(set.ok());
	HocpSplitMetric metric(*set, t.params.hocp, t.params.depthCheckMarginMm);
	ForestTrainerConfig fc;
	fc.seed = seed;
	t.forest = trainForest(fc, metric, set->labels);
	return t;
}

std::string readAll(const std::filesystem::path &p)
{
	std::ifstream f(p, std::ios::binary);
	return {std::istreambuf_iterator<char>(f), {}};
}

class EndToEnd : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		trained_ = new Trained(trainSmall(11));
		dir_ = new std::filesystem::path(test::freshTempDir("end_to_end"));
		ForestStorage storage(trained_->forest, TemplateEncoding::kUint8);
		ASSERT_TRUE(saveModelFile(*dir_ / "ape.ihf", trained_->params, trained_->mesh, storage.view()).ok());
		auto m = loadModelFile(*dir_ / "ape.ihf");
		ASSERT_TRUE(m.ok());
		model_ = m.value().release();
	}
	static void TearDownTestSuite()
	{
		delete model_;
		delete trained_;
		delete dir_;
	}

	// Training view i's appearance at t (the crop's rotation undone).
	static Pose viewAt(int i, const Eigen::Vector3d &t)
	{
		Pose p;
		p.t = t;
		p.R = rayAlignment(t) * sampleTrainingViews(trained_->set.views)[static_cast<size_t>(i)].pose.R;
		return p;
	}
	static void render(const Pose &pose, DepthImageMm &depth)
	{
		DepthRenderer renderer(model_->mesh().vertices.size());
		ASSERT_TRUE(renderer.render(model_->mesh(), pose, kKinect, depth.view()).ok());
	}

	static PixelBox clutteredScene(const Pose &gt, DepthImageMm &depth);
	// A cluttered scene where two refinement iterations' modes outrank the
	// registration's, and a config that refines there without half-turns.
	static PixelBox crowdedScene(DepthImageMm &depth)
	{
		return clutteredScene(viewAt(5, Eigen::Vector3d(-30, 20, 780)), depth);
	}
	static EstimatorConfig refining(int icpCandidates)
	{
		EstimatorConfig cfg;
		cfg.iterations = 2;
		cfg.icpCandidates = icpCandidates;
		cfg.halfTurns.candidates = 0;
		return cfg;
	}

	static Trained *trained_;
	static ObjectModel *model_;
	static std::filesystem::path *dir_;
};

Trained *EndToEnd::trained_ = nullptr;
ObjectModel *EndToEnd::model_ = nullptr;
std::filesystem::path *EndToEnd::dir_ = nullptr;

// The box around a depth image's valid pixels, 10 % wider on each side.
PixelBox boxAround(const DepthImageMm &depth)
{
	int x0 = depth.width(), y0 = depth.height(), x1 = 0, y1 = 0;
	for (int y = 0; y < depth.height(); ++y)
		for (int x = 0; x < depth.width(); ++x)
			if (depth.at(x, y) > 0) {
				x0 = std::min(x0, x);
				y0 = std::min(y0, y);
				x1 = std::max(x1, x);
				y1 = std::max(y1, y);
			}
	EXPECT_LT(x0, x1);
	const int mx = (x1 - x0) / 10 + 2, my = (y1 - y0) / 10 + 2;
	return PixelBox{x0 - mx, y0 - my, x1 - x0 + 1 + 2 * mx, y1 - y0 + 1 + 2 * my};
}

TEST_F(EndToEnd, RecoversAKnownPoseOnACleanRender)
{
	// The appearance of a training view, placed off the optical axis: the
	// virtual crop must undo the off-axis rotation for the votes to fit.
	const Pose gt = viewAt(37, Eigen::Vector3d(60, -40, 800));
	DepthImageMm depth(640, 480, 0.0f);
	render(gt, depth);
	const PixelBox box = boxAround(depth);

	PoseEstimator estimator;
	EstimatorConfig cfg;
	PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, cfg);
	ASSERT_TRUE(e.found) << e.reason;
	double add = addError(e.pose, gt, model_->mesh().vertices);
	EXPECT_LT(add, 0.1 * trained_->params.diameter)
		<< "rotation error " << rotationAngle(e.pose.R, gt.R) * 180 / M_PI << " deg, translation "
		<< (e.pose.t - gt.t).norm() << " mm";
	EXPECT_GT(e.confidence, 0.5f);
}

// The object at gt, a second one beside it, turned, and a wall behind both
// inside the box (clutter the registration votes on); returns the box.
PixelBox EndToEnd::clutteredScene(const Pose &gt, DepthImageMm &depth)
{
	render(gt, depth);
	const PixelBox box = boxAround(depth);
	DepthImageMm second(640, 480, 0.0f);
	render(viewAt(25, gt.t + Eigen::Vector3d(40, 10, 0)), second);
	for (int y = box.y; y < box.y + box.h; ++y)
		for (int x = box.x; x < box.x + box.w; ++x) {
			const float z = second.at(x, y);
			if (z > 0 && (depth.at(x, y) <= 0 || z < depth.at(x, y)))
				depth.at(x, y) = z;
			if (depth.at(x, y) <= 0)
				depth.at(x, y) = static_cast<float>(gt.t.z() + 60.0);
		}
	return box;
}

// Every hypothesis an estimate reports, in order.
struct RecordedEvents final : EstimateObserver {
	std::vector<HypothesisEvent> all;
	void onHypothesis(const HypothesisEvent &e) override { all.push_back(e); }
};

// Refinement's modes outrank some of the registration's; the registration's
// best distinct hypotheses are polished all the same (k = 5 polishes what
// k = 0 would), so refinement cannot lose a pose by crowding it out.
TEST_F(EndToEnd, RefinementPolishesTheRegistrationsCandidates)
{
	RecordedEvents events;
	DepthImageMm depth(640, 480, 0.0f);
	const PixelBox box = crowdedScene(depth);
	PoseEstimator estimator;
	estimator.setObserver(&events);
	EstimatorConfig cfg = refining(3);
	cfg.polishForestBests = false;
	auto polishedOfRegistration = [&]() {
		return std::count_if(events.all.begin(), events.all.end(), [](const HypothesisEvent &ev) {
			return std::string_view(ev.stage) == "icp" && ev.iteration == 0;
		});
	};
	ASSERT_TRUE(estimator.estimate(depth.view(), kKinect, box, *model_, cfg).found);
	const auto on = polishedOfRegistration();
	// The registration's three best distinct modes, each polished once.
	EXPECT_EQ(on, 3);

	events.all.clear();
	cfg.polishRegistration = false;
	ASSERT_TRUE(estimator.estimate(depth.view(), kKinect, box, *model_, cfg).found);
	// The scene is one where refinement's modes crowd some of them out.
	EXPECT_LT(polishedOfRegistration(), on);
}

// The pose returned is the best polished one, even where a proposal (a
// vote mode as scored) scored above every polish: the best of many guesses
// is the one whose score luck raised most.
TEST_F(EndToEnd, ThePoseReturnedIsThePolishedBest)
{
	RecordedEvents events;
	PoseEstimator estimator;
	estimator.setObserver(&events);
	const EstimatorConfig cfg = refining(3);
	int proposalAhead = 0;
	for (int v = 0; v < 12; ++v) {
		DepthImageMm depth(640, 480, 0.0f);
		const PixelBox box =
			clutteredScene(viewAt(3 * v + 1, Eigen::Vector3d(20.0 * (v % 3 - 1), 15.0 * (v % 2), 790)), depth);
		events.all.clear();
		const PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, cfg);
		ASSERT_TRUE(e.found) << e.reason;
		float bestPolished = -1, bestProposed = -1;
		bool returned = false;
		for (const HypothesisEvent &ev : events.all) {
			if (std::string_view(ev.stage) != "icp") {
				bestProposed = std::max(bestProposed, ev.score.score);
				continue;
			}
			bestPolished = std::max(bestPolished, ev.score.score);
			returned |= (ev.pose.t - e.pose.t).norm() < 1e-6 && (ev.pose.R - e.pose.R).norm() < 1e-9;
		}
		EXPECT_TRUE(returned) << "view " << v;
		EXPECT_TRUE(e.icpApplied) << "view " << v;
		EXPECT_EQ(e.score.score, bestPolished) << "view " << v;
		proposalAhead += bestProposed > bestPolished;
	}
	RecordProperty("proposal_ahead", proposalAhead);
	// Some scenes are ones where a proposal outscored every polished pose.
	EXPECT_GT(proposalAhead, 0);
}

// Votes cast per iteration (the registration's passes summed).
struct VotesPerIteration final : EstimateObserver {
	std::vector<size_t> votes;
	void onHypothesis(const HypothesisEvent &) override {}
	void onVotes(const VoteEvent &e) override
	{
		if (votes.size() <= static_cast<size_t>(e.iteration))
			votes.resize(static_cast<size_t>(e.iteration) + 1, 0);
		votes[static_cast<size_t>(e.iteration)] += e.votes.size();
	}
};

// A refinement iteration votes with its own bounds (fewer parts here, so
// fewer votes); the registration's vote is the one it was. Unset (0), an
// iteration votes as the registration.
TEST_F(EndToEnd, RefinementIterationsVoteWithTheirOwnBounds)
{
	DepthImageMm depth(640, 480, 0.0f);
	const Pose gt = viewAt(37, Eigen::Vector3d(60, -40, 800));
	const PixelBox box = clutteredScene(gt, depth);
	EstimatorConfig cfg = refining(1);
	iterationsAsRegistration(cfg);
	auto votesPerIteration = [&]() {
		VotesPerIteration seen;
		PoseEstimator estimator;
		estimator.setObserver(&seen);
		EXPECT_TRUE(estimator.estimate(depth.view(), kKinect, box, *model_, cfg).found);
		return seen.votes;
	};
	const std::vector<size_t> full = votesPerIteration();
	ASSERT_EQ(full.size(), 3u);
	cfg.iterationTargetParts = 2;
	cfg.iterationIbsMaxPoints = 200;
	cfg.iterationMaxShiftVotes = 256;
	const std::vector<size_t> lean = votesPerIteration();
	ASSERT_EQ(lean.size(), 3u);
	EXPECT_EQ(lean[0], full[0]);
	EXPECT_GT(lean[1], 0u);
	EXPECT_LT(2 * lean[1], full[1]);
	EXPECT_LT(2 * lean[2], full[2]);

	const EstimatorConfig it = forIterations(cfg);
	EXPECT_EQ(it.targetParts, 2);
	EXPECT_EQ(it.maxShiftVotes, 256);
	EXPECT_EQ(it.ibsMaxPoints, 200);
	EXPECT_EQ(it.ibsCgIterations, cfg.ibsCgIterations); // unset: as the registration's
	cfg.iterationTargetParts = 100000; // a bound never raises a setting
	EXPECT_EQ(forIterations(cfg).targetParts, cfg.targetParts);
}

// Refinement adds its modes to the ranking of the hypotheses to polish; the
// forest's own bests (the registration's and the last iteration's) are
// polished even when they rank below the polish's count, so refinement
// never drops a mode the registration alone would have polished.
TEST_F(EndToEnd, RefinementPolishesTheForestsOwnBests)
{
	RecordedEvents events;
	DepthImageMm depth(640, 480, 0.0f);
	const PixelBox box = crowdedScene(depth);
	PoseEstimator estimator;
	estimator.setObserver(&events);
	EstimatorConfig cfg = refining(1); // the ranking alone polishes only its best
	// Occluded 0.2 and box power 1 (the weights for modal boxes) and no
	// outline edge factor, under which this scene ranks both forest bests
	// below the first.
	cfg.score.occludedWeight = 0.2f;
	cfg.score.boxWeight = 1.0f;
	cfg.score.edgeShare = 0.0f;
	PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, cfg);
	ASSERT_TRUE(e.found) << e.reason;

	const double same = 0.05 * trained_->params.diameter;
	auto near = [&](const HypothesisEvent &a, const HypothesisEvent &b) {
		return (a.pose.t - b.pose.t).norm() < same && rotationAngle(a.pose.R, b.pose.R) < 10.0 * M_PI / 180.0;
	};
	// The best mode of each iteration, and of all (the ranking's first:
	// no view search runs on this model).
	std::vector<const HypothesisEvent *> bestOf(static_cast<size_t>(cfg.iterations) + 1, nullptr);
	const HypothesisEvent *top = nullptr;
	std::vector<int> polishedIterations;
	for (const HypothesisEvent &ev : events.all) {
		if (std::string_view(ev.stage) == "icp")
			polishedIterations.push_back(ev.iteration);
		if (std::string_view(ev.stage) != "mode")
			continue;
		const HypothesisEvent *&b = bestOf[static_cast<size_t>(ev.iteration)];
		if (!b || ev.score.score > b->score.score)
			b = &ev;
		if (!top || ev.score.score > top->score.score)
			top = &ev;
	}
	ASSERT_TRUE(top && bestOf[0] && bestOf[2]);
	auto polished = [&](int k) {
		return std::find(polishedIterations.begin(), polishedIterations.end(), k) != polishedIterations.end();
	};
	int forced = 0;
	if (!near(*bestOf[0], *top)) {
		EXPECT_TRUE(polished(0)) << "the registration's best mode was not polished";
		++forced;
	}
	if (!near(*bestOf[2], *top) && !near(*bestOf[2], *bestOf[0])) {
		EXPECT_TRUE(polished(2)) << "the last iteration's best mode was not polished";
		++forced;
	}
	// The scene is one where both forest bests rank below the first (the
	// only one the ranking polishes here).
	EXPECT_EQ(forced, 2);

	// Off ([icp] forest_bests = false; the registration's candidates are
	// its best here, so those off too): the ranking's first alone.
	events.all.clear();
	cfg.polishForestBests = false;
	cfg.polishRegistration = false;
	ASSERT_TRUE(estimator.estimate(depth.view(), kKinect, box, *model_, cfg).found);
	EXPECT_EQ(std::count_if(events.all.begin(), events.all.end(),
				[](const HypothesisEvent &ev) { return std::string_view(ev.stage) == "icp"; }),
		  1);
}

// The confidence's margin is the winner's score less the best score of any
// hypothesis the estimator reported that is a different pose (its model
// points, sampled as RivalPoses samples them, 0.1 diameter away on
// average): here the second object beside the first.
TEST_F(EndToEnd, TheMarginIsTheGapToTheBestDistinctHypothesis)
{
	RecordedEvents events;
	DepthImageMm depth(640, 480, 0.0f);
	const PixelBox box = clutteredScene(viewAt(5, Eigen::Vector3d(-30, 20, 780)), depth);
	EstimatorConfig cfg;
	cfg.iterations = 2;
	PoseEstimator estimator;
	estimator.setObserver(&events);
	PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, cfg);
	ASSERT_TRUE(e.found) << e.reason;

	const std::vector<Eigen::Vector3f> &v = model_->mesh().vertices;
	const size_t stride = (v.size() + kPoseDistancePoints - 1) / kPoseDistancePoints;
	const double distinctMm = cfg.confidence.distinctShare * trained_->params.diameter;
	float rival = 0;
	for (const HypothesisEvent &ev : events.all) {
		double sum = 0;
		int n = 0;
		for (size_t i = 0; i < v.size(); i += stride, ++n)
			sum += (ev.pose.apply(v[i].cast<double>()) - e.pose.apply(v[i].cast<double>())).norm();
		if (sum / n > distinctMm)
			rival = std::max(rival, ev.score.score);
	}
	EXPECT_GT(rival, 0.0f); // the second object, at least
	EXPECT_NEAR(e.margin, e.score.score - rival, 1e-5f);
	EXPECT_FLOAT_EQ(e.confidence, poseConfidence(e.score.score, e.margin, cfg.confidence));
	EXPECT_LE(e.confidence, e.score.score);

	// Off: the score alone.
	cfg.confidence.fullMargin = 0.0f;
	PoseEstimate off = estimator.estimate(depth.view(), kKinect, box, *model_, cfg);
	EXPECT_FLOAT_EQ(off.confidence, off.score.score);
	EXPECT_FLOAT_EQ(off.margin, e.margin); // measured either way
}

TEST_F(EndToEnd, BadBoxesGiveNoPoseWithAReason)
{
	DepthImageMm depth(640, 480, 0.0f);
	PoseEstimator estimator;
	EstimatorConfig cfg;
	PoseEstimate outside = estimator.estimate(depth.view(), kKinect, PixelBox{700, 10, 50, 50}, *model_, cfg);
	EXPECT_FALSE(outside.found);
	EXPECT_STREQ(outside.reason, "box outside the image");
	PoseEstimate empty = estimator.estimate(depth.view(), kKinect, PixelBox{10, 10, 0, 50}, *model_, cfg);
	EXPECT_FALSE(empty.found);
	EXPECT_STREQ(empty.reason, "empty box");
	PoseEstimate sparse = estimator.estimate(depth.view(), kKinect, PixelBox{10, 10, 50, 50}, *model_, cfg);
	EXPECT_FALSE(sparse.found);
	EXPECT_STREQ(sparse.reason, "too few valid depth pixels in the box");
}

TEST_F(EndToEnd, TrainingIsDeterministicFromTheSeed)
{
	Trained again = trainSmall(11);
	ForestStorage a(trained_->forest, TemplateEncoding::kUint8), b(again.forest, TemplateEncoding::kUint8);
	ASSERT_TRUE(saveModelFile(*dir_ / "a.ihf", trained_->params, trained_->mesh, a.view()).ok());
	ASSERT_TRUE(saveModelFile(*dir_ / "b.ihf", again.params, again.mesh, b.view()).ok());
	EXPECT_EQ(readAll(*dir_ / "a.ihf"), readAll(*dir_ / "b.ihf"));
}

} // namespace
} // namespace ihf
