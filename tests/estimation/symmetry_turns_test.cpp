// SPDX-License-Identifier: MIT
// A nearly symmetric object end to end: a cup (core/synth/household_objects.h)
// trained small, its near-symmetry found at training, rendered in front of a
// wall. Seen with its handle to the side, it is placed with the handle
// right and not flagged, and placed right through a window too coarse to
// show the handle (the turns compared on a finer one); seen with the
// handle hidden behind its body, the pose comes back flagged ambiguous
// about the cup's axis, its confidence scaled down, and so does every pose
// that tracks it in the frames after, until a frame's spare time (or, in
// an unbudgeted stream, every frame) detects it again with the handle come
// into view. The comparisons behind each verdict reach the estimator's
// observer.
// The stage alone, given the cup upside down and slid along its axis as the
// best, takes the truth among the reported poses unless its score lies far
// below, and leaves a turn about the axis to the turns; given it upside
// down in place, sets it upright by its end-over-end turn; a reported turn
// between the turns' steps is compared at its own angle.

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/estimation/hough_voter.h"
#include "core/estimation/hypothesis_polisher.h"
#include "core/estimation/pose_estimator.h"
#include "core/estimation/symmetry_rivals.h"
#include "core/estimation/symmetry_turn_config.h"
#include "core/eval/pose_error.h"
#include "core/forest/forest_trainer.h"
#include "core/geometry/mesh_simplify.h"
#include "core/pose/half_turns.h"
#include "core/render/depth_renderer.h"
#include "core/synth/household_objects.h"
#include "core/tracking/stream_estimator.h"
#include "core/training/hocp_split_metric.h"
#include "core/training/near_symmetry_finder.h"
#include "core/training/training_set.h"
#include "core/training/view_template_builder.h"
#include "tests/common/part_pixels.h"
#include "tests/runtime/small_model.h"

namespace ihf {
namespace {

const CameraIntrinsics kKinect{572.4114, 573.57043, 325.2611, 242.04899, 640, 480};
constexpr double kDeg = M_PI / 180.0;

class SymmetryTurns : public ::testing::Test
{
protected:
	static void SetUpTestSuite()
	{
		Mesh mesh = makeCup();
		ModelParams params;
		params.objId = 31;
		params.diameter = meshDiameter(mesh);
		TrainingSetConfig set;
		set.views.viewpoints = 40;
		set.views.inplaneSteps = 4;
		set.views.minDistance = 650;
		set.views.maxDistance = 800;
		set.views.seed = 3;
		set.scales = {1.0f};
		set.partsPerImage = 20;
		set.seed = 3;
		auto training = buildTrainingSet(mesh, kKinect, params, set);
		ASSERT_TRUE(training.ok()) << training.error().message;
		HocpSplitMetric metric(*training, params.hocp, params.depthCheckMarginMm);
		ForestTrainerConfig fc;
		fc.seed = 3;
		const HoughForest forest = trainForest(fc, metric, training->labels);
		std::vector<NearSymmetry> symmetries = findNearSymmetries(mesh);
		auto *model = new OwnedObjectModel(params, mesh, ForestStorage(forest, TemplateEncoding::kUint8));
		model->setNearSymmetries(std::move(symmetries));
		auto points = buildViewTemplatePoints(model->mesh(), params.diameter, ViewTemplateConfig{});
		ASSERT_TRUE(points.ok());
		model->attachViewTemplates(ViewTemplateConfig{}.viewpoints, ViewTemplateConfig{}.pointsPerView,
					   std::move(*points));
		auto simple = simplifyMesh(model->mesh(), 0.5);
		ASSERT_TRUE(simple.ok());
		model->attachRenderMesh(std::move(simple->mesh));
		model_ = model;
	}
	static void TearDownTestSuite() { delete model_; }

	// The cup seen from azimuth `azimuthDeg` (0: the camera on the handle's
	// side, +x) and elevation `elevationDeg`, 720 mm from its middle.
	static Pose viewOfCup(double azimuthDeg, double elevationDeg)
	{
		const Eigen::Vector3d target(0, 0, 47);
		const double a = azimuthDeg * kDeg, e = elevationDeg * kDeg;
		const Eigen::Vector3d camera =
			target + 720.0 * Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
		const Eigen::Vector3d f = (target - camera).normalized();
		const Eigen::Vector3d right = f.cross(Eigen::Vector3d::UnitZ()).normalized();
		const Eigen::Vector3d down = f.cross(right);
		Pose p;
		p.R.row(0) = right.transpose();
		p.R.row(1) = down.transpose();
		p.R.row(2) = f.transpose();
		p.t = -p.R * camera;
		return p;
	}

	// The cup rendered at gt, a wall 200 mm behind it; returns the box round
	// the cup, 10 % wider on each side.
	static PixelBox scene(const Pose &gt, DepthImageMm &depth)
	{
		DepthRenderer renderer(model_->mesh().vertices.size());
		EXPECT_TRUE(renderer.render(model_->mesh(), gt, kKinect, depth.view()).ok());
		int x0 = depth.width(), y0 = depth.height(), x1 = 0, y1 = 0;
		for (int y = 0; y < depth.height(); ++y)
			for (int x = 0; x < depth.width(); ++x)
				if (depth.at(x, y) > 0) {
					x0 = std::min(x0, x);
					y0 = std::min(y0, y);
					x1 = std::max(x1, x);
					y1 = std::max(y1, y);
				} else {
					depth.at(x, y) = static_cast<float>(gt.t.z() + 200.0);
				}
		const int mx = (x1 - x0) / 10 + 2, my = (y1 - y0) / 10 + 2;
		return PixelBox{x0 - mx, y0 - my, x1 - x0 + 1 + 2 * mx, y1 - y0 + 1 + 2 * my};
	}

	// clear with an occluder 150 mm in front of the cup over its handle
	// and a little past it.
	static DepthImageMm handleHidden(const Pose &gt, const DepthImageMm &clear)
	{
		DepthImageMm occluded = clear;
		auto handle = test::partPixels(model_->mesh(), makeCup(false), gt, kKinect);
		EXPECT_TRUE(handle.ok()) << handle.error().message;
		if (!handle.ok())
			return occluded;
		const int r = 4;
		const int w = clear.width(), h = clear.height();
		for (int y = 0; y < h; ++y)
			for (int x = 0; x < w; ++x) {
				if (!handle->at(x, y))
					continue;
				for (int v = std::max(0, y - r); v <= std::min(h - 1, y + r); ++v)
					for (int u = std::max(0, x - r); u <= std::min(w - 1, x + r); ++u)
						occluded.at(u, v) = static_cast<float>(gt.t.z() - 150.0);
			}
		return occluded;
	}

	// Frame f of a stream with the one box, inside budgetMs (0: unbudgeted).
	static StreamResult streamFrame(StreamEstimator &stream, const StreamBox &box, int f, const DepthImageMm &depth,
					float budgetMs)
	{
		StreamResult r;
		stream.estimateFrame(static_cast<uint64_t>(f), depth.view(), kKinect, std::span<const StreamBox>(&box, 1),
				     EstimatorConfig{}, budgetMs, std::span<StreamResult>(&r, 1));
		EXPECT_TRUE(r.estimate.found) << "frame " << f << ": " << r.estimate.reason;
		return r;
	}

	// The angle (deg) between the estimate's and the truth's handle
	// directions, seen along the cup's axis.
	static double handleAngleDeg(const Pose &est, const Pose &gt)
	{
		const Eigen::Vector3d up = gt.R.col(2);
		auto flat = [&](const Eigen::Vector3d &v) { return (v - up * up.dot(v)).normalized(); };
		return std::acos(std::clamp(flat(est.R.col(0)).dot(flat(gt.R.col(0))), -1.0, 1.0)) / kDeg;
	}

	static OwnedObjectModel *model_;
};

OwnedObjectModel *SymmetryTurns::model_ = nullptr;

TEST_F(SymmetryTurns, TrainingFindsTheCupsAxis)
{
	ASSERT_FALSE(model_->nearSymmetries().empty());
	EXPECT_TRUE(model_->nearSymmetries()[0].continuous());
	EXPECT_GT(std::abs(model_->nearSymmetries()[0].axis.z()), 0.99f);
}

TEST_F(SymmetryTurns, HandleVisibleIsPlacedRight)
{
	for (double azimuth : {-90.0, 60.0}) {
		const Pose gt = viewOfCup(azimuth, 25.0);
		DepthImageMm depth(640, 480, 0.0f);
		const PixelBox box = scene(gt, depth);
		PoseEstimator estimator;
		const PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, EstimatorConfig{});
		ASSERT_TRUE(e.found) << e.reason;
		EXPECT_LT(handleAngleDeg(e.pose, gt), 15.0) << "azimuth " << azimuth;
		EXPECT_LT(addError(e.pose, gt, model_->mesh().vertices), 0.1 * model_->params().diameter)
			<< "azimuth " << azimuth;
		EXPECT_FALSE(e.ambiguous) << "azimuth " << azimuth;
		EXPECT_GT(e.confidence, 0.5f) << "azimuth " << azimuth;
	}
}

TEST_F(SymmetryTurns, HandleHiddenIsFlaggedAmbiguous)
{
	// The camera opposite the handle, low enough for the body to hide it.
	const Pose gt = viewOfCup(180.0, 8.0);
	DepthImageMm depth(640, 480, 0.0f);
	const PixelBox box = scene(gt, depth);
	PoseEstimator estimator;
	const PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, EstimatorConfig{});
	ASSERT_TRUE(e.found) << e.reason;
	EXPECT_TRUE(e.ambiguous);
	// About the cup's axis, and the cup itself in place.
	EXPECT_GT(std::abs(e.ambiguityAxis.dot(gt.R.col(2))), 0.97);
	EXPECT_LT((e.pose.apply(Eigen::Vector3d(0, 0, 47)) - gt.apply(Eigen::Vector3d(0, 0, 47))).norm(), 10.0);
	EXPECT_LE(e.confidence, 0.5f * e.score.score + 1e-6f);

	// Without the comparison the same box says nothing of it.
	EstimatorConfig off;
	off.symmetryTurns.enabled = false;
	const PoseEstimate plain = estimator.estimate(depth.view(), kKinect, box, *model_, off);
	ASSERT_TRUE(plain.found);
	EXPECT_FALSE(plain.ambiguous);
}

// The comparisons behind a verdict reach the observer (ihf estimate
// --trace writes them): with the handle in view every distinct turn of the
// last round is beaten by the lead the verdict asks; with it hidden one is
// not, which is why the pose is flagged.
class ComparisonRecorder : public EstimateObserver
{
public:
	void onHypothesis(const HypothesisEvent &) override {}
	void onComparison(const ComparisonEvent &e) override { events.push_back(e); }

	// The last round's turns that count in the verdict.
	std::vector<ComparisonEvent> lastRoundTurns() const
	{
		int last = -1;
		for (const ComparisonEvent &e : events)
			if (std::string_view(e.kind) == "turn")
				last = std::max(last, e.round);
		std::vector<ComparisonEvent> out;
		for (const ComparisonEvent &e : events)
			if (std::string_view(e.kind) == "turn" && e.round == last && e.distinct && !e.reported)
				out.push_back(e);
		return out;
	}

	std::vector<ComparisonEvent> events;
};

bool beatenDecisively(const ComparisonEvent &e)
{
	return decisivelyBy(e.evidence.forA, e.evidence.forB, e.evidence.informative,
			    SymmetryTurnConfig{.minPixels = e.minPixels});
}

TEST_F(SymmetryTurns, TheComparisonsBehindTheVerdictAreReported)
{
	const Eigen::Vector3d middle(0, 0, 47);
	for (const auto &[azimuth, elevation] : {std::pair{60.0, 25.0}, std::pair{180.0, 8.0}}) {
		const Pose gt = viewOfCup(azimuth, elevation);
		DepthImageMm depth(640, 480, 0.0f);
		const PixelBox box = scene(gt, depth);
		PoseEstimator estimator;
		ComparisonRecorder recorder;
		estimator.setObserver(&recorder);
		const PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, EstimatorConfig{});
		ASSERT_TRUE(e.found) << e.reason;
		const std::vector<ComparisonEvent> turns = recorder.lastRoundTurns();
		ASSERT_FALSE(turns.empty()) << "azimuth " << azimuth;
		int beaten = 0;
		for (const ComparisonEvent &t : turns) {
			EXPECT_EQ(t.evidence.forA + t.evidence.forB, t.evidence.informative);
			EXPECT_LE(t.evidence.informative, t.evidence.differing);
			EXPECT_GT(std::abs(t.axis.z()), 0.99) << "a turn about the cup's axis";
			// A turn about the cup's axis leaves its middle in place, in
			// the real camera's frame.
			if (!t.polished) {
				EXPECT_LT((t.rival.apply(middle) - e.pose.apply(middle)).norm(), 10.0);
			}
			beaten += beatenDecisively(t);
		}
		if (e.ambiguous)
			EXPECT_LT(beaten, static_cast<int>(turns.size())) << "azimuth " << azimuth;
		else
			EXPECT_EQ(beaten, static_cast<int>(turns.size())) << "azimuth " << azimuth;
		EXPECT_EQ(e.ambiguous, azimuth == 180.0);
	}
}

// A box seen through a coarse window (a budget's, downsampled to at most
// 300 pixels here: the handle then covers a pixel or two) compares the
// cup's turns on the box cropped again at the estimator's full window, and
// the handle is placed right. With the estimator's limit as coarse as the
// box's window they are compared there, and the handle is turned wrong.
TEST_F(SymmetryTurns, ACoarseWindowComparesTheTurnsAtFullResolution)
{
	EstimatorConfig coarse;
	coarse.windowPixels = 300;
	EstimatorLimits coarseLimits;
	coarseLimits.maxWindowPixels = coarse.windowPixels;
	// A view from above where the handle's few coarse pixels mislead (of
	// 44 views at 30 deg steps of azimuth and 20-35 deg of elevation, the
	// one where the coarse window alone turns the handle wrong and the
	// full one does not).
	for (const auto &[azimuth, elevation] : {std::pair{240.0, 20.0}}) {
		const Pose gt = viewOfCup(azimuth, elevation);
		DepthImageMm depth(640, 480, 0.0f);
		const PixelBox box = scene(gt, depth);

		PoseEstimator estimator;
		const PoseEstimate e = estimator.estimate(depth.view(), kKinect, box, *model_, coarse);
		ASSERT_TRUE(e.found) << e.reason;
		EXPECT_LT(handleAngleDeg(e.pose, gt), 15.0) << azimuth;
		EXPECT_LT(addError(e.pose, gt, model_->mesh().vertices), 0.1 * model_->params().diameter) << azimuth;

		PoseEstimator limited(coarseLimits);
		const PoseEstimate c = limited.estimate(depth.view(), kKinect, box, *model_, coarse);
		ASSERT_TRUE(c.found) << c.reason;
		EXPECT_GT(handleAngleDeg(c.pose, gt), 15.0) << azimuth << ": the coarse window alone tells the handle";
	}
}

// The stage's source alone on a 200 x 200 window of a clean cup: the pool
// holds the reported poses, `best` is what the estimator would hand it.
class CloseRivalBox
{
public:
	CloseRivalBox(const OwnedObjectModel &model, const Pose &gt, const EstimatorConfig &config)
		: workspace_(EstimatorLimits{}), planner_(nullptr), voter_(workspace_, planner_.timer(), peaks_),
		  config_(config)
	{
		workspace_.attachPool(pool_);
		EXPECT_TRUE(workspace_.valid());
		EXPECT_TRUE(workspace_.beginBox(kWindow.width, kWindow.height));
		DepthRenderer renderer(model.mesh().vertices.size());
		EXPECT_TRUE(renderer.render(model.mesh(), gt, kWindow, workspace_.observed()).ok());
		workspace_.maskAll();
		scorer_.emplace(workspace_, ScoreWindow{workspace_.observed(), kWindow, OpenSides{}, &config_.score}, model);
		polisher_.emplace(workspace_, voter_, planner_.timer(), *scorer_, config_);
		pool_.beginBox(Eigen::Matrix3d::Identity(), model.params().diameter, 0);
		parts_.emplace(workspace_, model, scorer_->window(), kWindow.width * kWindow.height);
		box_.emplace(ProposalBox{config_, model, BoxAxes{}, boundingBox(model.mesh()).centre().cast<double>(), 0, 0,
					 workspace_, *scorer_, pool_, *polisher_, planner_, *parts_});
	}
	~CloseRivalBox() { workspace_.endBox(); }

	// pose scored and reported, as every hypothesis of a box is.
	Hypothesis report(const Pose &pose)
	{
		Hypothesis h;
		h.valid = true;
		h.pose = pose;
		h.score = scorer_->score(pose);
		pool_.report(h, "test", 0);
		return h;
	}
	ProposalBox &box() { return *box_; }
	void observe(EstimateObserver *observer) { pool_.setObserver(observer); }

	static constexpr CameraIntrinsics kWindow{572.4114, 573.57043, 100, 100, 200, 200};

private:
	EstimatorWorkspace workspace_;
	BudgetPlanner planner_;
	EstimatorPeaks peaks_;
	HoughVoter voter_;
	CandidatePool pool_;
	EstimatorConfig config_;
	std::optional<BoxScorer> scorer_;
	std::optional<HypothesisPolisher> polisher_;
	std::optional<PartWindow> parts_;
	std::optional<ProposalBox> box_;
};

// The events of one stage.
class StageEvents : public EstimateObserver
{
public:
	explicit StageEvents(std::string_view stage) : stage_(stage) {}
	void onHypothesis(const HypothesisEvent &e) override
	{
		if (stage_ == e.stage)
			poses.push_back(e.pose);
	}
	std::vector<Pose> poses;

private:
	std::string_view stage_;
};

// The cup in front of the window's camera, its axis across the view, the
// handle to the side; and the same cup upside down (a half-turn about its x
// axis through its middle) slid 40 mm along its axis: it fits what it
// covers of the cup, and it is no turn of the truth about the cup's axis.
Pose uprightCup()
{
	Pose p;
	p.R = Eigen::AngleAxisd(-100 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
	p.t = Eigen::Vector3d(0, 0, 700) - p.R * Eigen::Vector3d(0, 0, 47);
	return p;
}

Pose upsideDownSlid(const Pose &gt)
{
	Pose p = turnedAbout(gt, Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix(),
			     Eigen::Vector3d(0, 0, 47));
	p.t += 40.0 * gt.R.col(2);
	return p;
}

TEST_F(SymmetryTurns, ACloseRivalTheDepthPrefersReplacesTheBest)
{
	const Pose gt = uprightCup();
	EstimatorConfig config;
	config.icp = false; // the rivals as reported, not polished
	CloseRivalBox scene(*model_, gt, config);
	const double right = 0.1 * model_->params().diameter;
	const Hypothesis best = scene.report(upsideDownSlid(gt));
	scene.report(gt);
	ASSERT_GT(addError(best.pose, gt, model_->mesh().vertices), right);

	StageEvents replaced("close_rival");
	scene.observe(&replaced);
	SymmetryRivalSource source;
	const Hypothesis chosen = source.propose(scene.box(), best, {});
	ASSERT_TRUE(chosen.valid);
	EXPECT_TRUE(source.verdict().turned);
	ASSERT_EQ(replaced.poses.size(), 1u);
	EXPECT_LT(addError(replaced.poses[0], gt, model_->mesh().vertices), right);
	EXPECT_LT(addError(chosen.pose, gt, model_->mesh().vertices), right);

	// Without close rivals the turns about the axis never reach it.
	config.symmetryTurns.closeRivals = 0;
	CloseRivalBox without(*model_, gt, config);
	without.report(gt);
	const Hypothesis alone = source.propose(without.box(), without.report(upsideDownSlid(gt)), {});
	EXPECT_GT(addError(alone.pose, gt, model_->mesh().vertices), right);
}

TEST_F(SymmetryTurns, ACloseRivalScoringFarBelowTheBestIsRefused)
{
	// The same box, the best's score raised past the truth's by more than
	// close_loss: the depth where they differ prefers the truth, but it is
	// not taken.
	const Pose gt = uprightCup();
	EstimatorConfig config;
	config.icp = false;
	CloseRivalBox scene(*model_, gt, config);
	Hypothesis best = scene.report(upsideDownSlid(gt));
	const Hypothesis truth = scene.report(gt);
	best.score.score = truth.score.score + 2 * config.symmetryTurns.closeLoss;
	StageEvents refused("close_rival_refused");
	scene.observe(&refused);
	SymmetryRivalSource source;
	const Hypothesis chosen = source.propose(scene.box(), best, {});
	EXPECT_EQ(refused.poses.size(), 1u);
	EXPECT_GT(addError(chosen.pose, gt, model_->mesh().vertices), 0.1 * model_->params().diameter);
}

TEST_F(SymmetryTurns, ACupUpsideDownInPlaceIsSetUpright)
{
	// The best is the cup upside down about its middle, its handle where
	// the truth's is; no reported pose is near the truth and no turn about
	// the cup's axis sets it upright. Its end-over-end turn does, and is
	// no near-symmetry: the verdict stays the axis turns', decisive with
	// the handle in view.
	const Pose gt = uprightCup();
	EstimatorConfig config;
	config.icp = false;
	config.symmetryTurns.closeRivals = 0;
	CloseRivalBox scene(*model_, gt, config);
	const Eigen::Matrix3d overTheHandle = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
	const Hypothesis best = scene.report(turnedAbout(gt, overTheHandle, Eigen::Vector3d(0, 0, 47)));
	const double right = 0.1 * model_->params().diameter;
	ASSERT_GT(addError(best.pose, gt, model_->mesh().vertices), right);
	SymmetryRivalSource source;
	const Hypothesis chosen = source.propose(scene.box(), best, {});
	ASSERT_TRUE(chosen.valid);
	EXPECT_TRUE(source.verdict().turned);
	EXPECT_LT(addError(chosen.pose, gt, model_->mesh().vertices), 2.0);
	EXPECT_TRUE(source.verdict().decisive);
	EXPECT_FALSE(source.verdict().ambiguous);
}

TEST_F(SymmetryTurns, ATurnAboutTheAxisIsLeftToTheTurns)
{
	// The best is the truth turned 90 deg about the cup's axis: the truth,
	// reported, is one of its turns, compared as such and not as a close
	// rival; it wins there all the same.
	const Pose gt = uprightCup();
	EstimatorConfig config;
	config.icp = false;
	CloseRivalBox scene(*model_, gt, config);
	const Hypothesis best = scene.report(
		turnedAbout(gt, Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(), Eigen::Vector3d::Zero()));
	scene.report(gt);
	StageEvents replaced("close_rival");
	SymmetryRivalSource source;
	scene.observe(&replaced);
	const Hypothesis chosen = source.propose(scene.box(), best, {});
	EXPECT_TRUE(replaced.poses.empty());
	EXPECT_LT(handleAngleDeg(chosen.pose, gt), 15.0);
}

TEST_F(SymmetryTurns, AReportedTurnBetweenTheStepsIsComparedAtItsOwnAngle)
{
	// The best is the truth turned 52 deg about the cup's axis, between the
	// comparison's 15 deg steps (the nearest land 7 and 8 deg beside the
	// handle); the truth, reported, is compared at its own angle and wins.
	const Pose gt = uprightCup();
	EstimatorConfig config;
	config.icp = false;
	CloseRivalBox scene(*model_, gt, config);
	const Hypothesis best = scene.report(turnedAbout(
		gt, Eigen::AngleAxisd(52 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix(), Eigen::Vector3d::Zero()));
	scene.report(gt);
	SymmetryRivalSource source;
	const Hypothesis chosen = source.propose(scene.box(), best, {});
	ASSERT_TRUE(chosen.valid);
	EXPECT_TRUE(source.verdict().turned);
	EXPECT_LT(handleAngleDeg(chosen.pose, gt), 1.0);
	EXPECT_LT(addError(chosen.pose, gt, model_->mesh().vertices), 1.0);
}

TEST_F(SymmetryTurns, TrackedHiddenHandleStaysAmbiguous)
{
	// The hidden-handle view, the cup sliding 2 mm a frame: detected in the
	// first frame, followed after; every tracked pose carries the flag, about
	// the cup's axis, its confidence scaled down as the detection's was.
	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	ASSERT_TRUE(stream.valid());
	const Pose start = viewOfCup(180.0, 8.0);
	int trackedFrames = 0;
	for (int f = 0; f < 4; ++f) {
		Pose gt = start;
		gt.t.x() += 2.0 * f;
		DepthImageMm depth(640, 480, 0.0f);
		const StreamBox box{31, scene(gt, depth), 0, model_};
		StreamResult r;
		stream.estimateFrame(static_cast<uint64_t>(f), depth.view(), kKinect, std::span<const StreamBox>(&box, 1),
				     EstimatorConfig{}, 0.0f, std::span<StreamResult>(&r, 1));
		ASSERT_TRUE(r.estimate.found) << "frame " << f << ": " << r.estimate.reason;
		EXPECT_EQ(r.mode, f == 0 ? BoxMode::kDetect : BoxMode::kTrack) << "frame " << f;
		trackedFrames += r.mode == BoxMode::kTrack;
		EXPECT_TRUE(r.estimate.ambiguous) << "frame " << f;
		EXPECT_GT(std::abs(r.estimate.ambiguityAxis.dot(gt.R.col(2))), 0.97) << "frame " << f;
		EXPECT_LE(r.estimate.confidence, 0.5f * r.estimate.score.score + 1e-6f) << "frame " << f;
	}
	EXPECT_EQ(trackedFrames, 3);
}

TEST_F(SymmetryTurns, ATrackedAmbiguousCupIsToldApartOnceItsHandleShows)
{
	// The handle to the side, behind an occluder for the first frames, then
	// in view; budgeted frames (a step clock) with time to detect the
	// tracked box again. The track carries its detection's flag while the
	// handle is hidden; the first detection that tells the turns apart
	// settles it: the tracked pose is flagged no more and is as confident
	// as any told apart.
	const Pose gt = viewOfCup(60.0, 25.0);
	DepthImageMm clear(640, 480, 0.0f);
	const PixelBox box = scene(gt, clear);
	const DepthImageMm occluded = handleHidden(gt, clear);

	test::StepClock clock(1000000); // 1 ms a read
	PoseEstimator detector({}, &clock);
	TrackerConfig tc;
	tc.detectMinMs = 20;
	StreamEstimator stream(detector, tc, &clock);
	ASSERT_TRUE(stream.valid());
	const StreamBox sbox{31, box, 0, model_};
	auto frame = [&](int f, const DepthImageMm &depth) { return streamFrame(stream, sbox, f, depth, 500.0f); };

	const StreamResult first = frame(0, occluded);
	ASSERT_EQ(first.mode, BoxMode::kDetect);
	ASSERT_TRUE(first.estimate.ambiguous) << "the occluder must hide the handle from the detection";
	const StreamResult hidden = frame(1, occluded);
	EXPECT_EQ(hidden.mode, BoxMode::kTrack);
	EXPECT_EQ(stream.stats().refreshed, 1u);
	EXPECT_TRUE(hidden.estimate.ambiguous) << "a detection that cannot tell the turns apart settles nothing";
	EXPECT_EQ(stream.stats().refreshSettled, 0u);

	const StreamResult shown = frame(2, clear);
	EXPECT_EQ(stream.stats().refreshed, 2u);
	EXPECT_EQ(stream.stats().refreshSettled, 1u);
	EXPECT_FALSE(shown.estimate.ambiguous);
	EXPECT_LT(handleAngleDeg(shown.estimate.pose, gt), 15.0);
	EXPECT_LT(addError(shown.estimate.pose, gt, model_->mesh().vertices), 0.1 * model_->params().diameter);
	EXPECT_GT(shown.estimate.confidence, 0.5f * shown.estimate.score.score);
	// And so it stays while it is tracked.
	const StreamResult after = frame(3, clear);
	EXPECT_FALSE(after.estimate.ambiguous);
}

TEST_F(SymmetryTurns, AnUnbudgetedStreamDetectsItsAmbiguousTracksAgain)
{
	// The same scene in unbudgeted frames, which have no spare time: each
	// frame detects the ambiguous track again. The first detection, the
	// handle hidden, turns it well away from the truth, and nothing in the
	// tracked frames moves it; the first detection that sees the handle
	// replaces it, unflagged, and the track is not detected again.
	const Pose gt = viewOfCup(60.0, 25.0);
	DepthImageMm clear(640, 480, 0.0f);
	const PixelBox box = scene(gt, clear);
	const DepthImageMm occluded = handleHidden(gt, clear);

	PoseEstimator detector;
	StreamEstimator stream(detector, TrackerConfig{});
	ASSERT_TRUE(stream.valid());
	const StreamBox sbox{31, box, 0, model_};
	auto frame = [&](int f, const DepthImageMm &depth) { return streamFrame(stream, sbox, f, depth, 0.0f); };

	const StreamResult first = frame(0, occluded);
	ASSERT_EQ(first.mode, BoxMode::kDetect);
	ASSERT_TRUE(first.estimate.ambiguous) << "the occluder must hide the handle from the detection";
	ASSERT_GT(handleAngleDeg(first.estimate.pose, gt), 90.0) << "this scene's hidden handle is guessed wrong";
	const StreamResult hidden = frame(1, occluded);
	EXPECT_EQ(hidden.mode, BoxMode::kTrack);
	EXPECT_EQ(stream.stats().refreshed, 1u);
	EXPECT_EQ(stream.stats().refreshWins, 0u) << "a detection that cannot tell the turns apart changes nothing";
	EXPECT_TRUE(hidden.estimate.ambiguous);
	EXPECT_GT(handleAngleDeg(hidden.estimate.pose, gt), 90.0);

	const StreamResult shown = frame(2, clear);
	EXPECT_EQ(shown.mode, BoxMode::kDetect);
	EXPECT_EQ(stream.stats().refreshed, 2u);
	EXPECT_EQ(stream.stats().refreshWins, 1u);
	EXPECT_FALSE(shown.estimate.ambiguous);
	EXPECT_LT(handleAngleDeg(shown.estimate.pose, gt), 15.0);
	EXPECT_LT(addError(shown.estimate.pose, gt, model_->mesh().vertices), 0.1 * model_->params().diameter);

	const StreamResult after = frame(3, clear);
	EXPECT_EQ(after.mode, BoxMode::kTrack);
	EXPECT_EQ(stream.stats().refreshed, 2u) << "a settled track is not detected again";
	EXPECT_FALSE(after.estimate.ambiguous);
}

} // namespace
} // namespace ihf
