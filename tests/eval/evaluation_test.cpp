// SPDX-License-Identifier: MIT
// evaluatePoses() on hand-made ground truth and estimates: F1 per z,
// recall at 0.1 diameter, matching per image, times and means.

#include <cmath>

#include <gtest/gtest.h>

#include "core/eval/evaluation.h"
#include "core/eval/visible_surface.h"

namespace ihf {
namespace {

// Corners of a 60 x 40 x 20 box: diameter sqrt(60^2 + 40^2 + 20^2).
std::vector<Eigen::Vector3f> boxPoints()
{
	std::vector<Eigen::Vector3f> pts;
	for (float x : {-30.f, 30.f})
		for (float y : {-20.f, 20.f})
			for (float z : {-10.f, 10.f})
				pts.push_back({x, y, z});
	return pts;
}

Pose poseAt(double x, double y, double z)
{
	Pose p;
	p.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
	p.t = {x, y, z};
	return p;
}

ResultRow row(int im, int obj, double score, const Pose &pose, double time = -1)
{
	ResultRow r;
	r.sceneId = 1;
	r.imId = im;
	r.objId = obj;
	r.score = score;
	r.pose = pose;
	r.time = time;
	return r;
}

TEST(Evaluation, ZValuesAreElevenSteps)
{
	const auto z = defaultZValues();
	ASSERT_EQ(z.size(), 11u);
	EXPECT_DOUBLE_EQ(z.front(), 0.05);
	EXPECT_DOUBLE_EQ(z[5], 0.10);
	EXPECT_DOUBLE_EQ(z.back(), 0.15);
}

TEST(Evaluation, OffsetJustAboveTenthOfDiameter)
{
	const double phi = 100.0;
	ObjectPoseError error(boxPoints(), PoseMetric::kAdd);
	std::map<int, EvalObject> objects = {{3, {phi, &error}}};

	const Pose gt = poseAt(10, 20, 700);
	Pose est = gt;
	est.t.x() += 0.1 * phi + 1e-6; // ADD of a translation is its length
	EvalReport r = evaluatePoses(objects, {{1, 0, 3, gt}}, {row(0, 3, 0.8, est)});

	ASSERT_EQ(r.objects.size(), 1u);
	const ObjectEvalResult &o = r.objects[0];
	EXPECT_EQ(o.numGt, 1u);
	EXPECT_EQ(o.numEstimates, 1u);
	EXPECT_EQ(o.metric, PoseMetric::kAdd);
	for (size_t i = 0; i < r.zValues.size(); ++i)
		EXPECT_EQ(o.f1[i], r.zValues[i] >= 0.11 - 1e-12 ? 1.0 : 0.0) << "z " << r.zValues[i];
	EXPECT_DOUBLE_EQ(o.meanF1, 5.0 / 11.0);
	EXPECT_EQ(o.recall, 0.0);

	// Just below: correct from z = 0.10.
	est.t.x() = gt.t.x() + 0.1 * phi - 1e-6;
	r = evaluatePoses(objects, {{1, 0, 3, gt}}, {row(0, 3, 0.8, est)});
	EXPECT_EQ(r.objects[0].f1[4], 0.0); // z = 0.09
	EXPECT_EQ(r.objects[0].f1[5], 1.0); // z = 0.10
	EXPECT_EQ(r.objects[0].recall, 1.0);
}

TEST(Evaluation, HandBuiltSetOfTenTruths)
{
	ObjectPoseError error(boxPoints(), PoseMetric::kAdd);
	const double phi = 70.0;
	std::map<int, EvalObject> objects = {{1, {phi, &error}}};

	// Ten images, one instance each. Images 0-5: exact estimates (scores
	// 0.9 .. 0.4); images 6, 7: estimates 100 mm off with the highest
	// scores; images 8, 9: nothing.
	std::vector<EvalGt> gts;
	std::vector<ResultRow> est;
	for (int im = 0; im < 10; ++im) {
		const Pose gt = poseAt(im * 10.0, -5.0, 800);
		gts.push_back({1, im, 1, gt});
		if (im < 6)
			est.push_back(row(im, 1, 0.9 - 0.1 * im, gt, 0.1 * (im + 1)));
		else if (im < 8)
			est.push_back(row(im, 1, 0.99 - 0.01 * (im - 6), poseAt(im * 10.0 + 100, -5, 800),
					  im == 6 ? -1 : 0.7));
	}

	EvalReport r = evaluatePoses(objects, gts, est);
	const ObjectEvalResult &o = r.objects[0];
	EXPECT_EQ(o.numGt, 10u);
	EXPECT_EQ(o.numEstimates, 8u);
	EXPECT_EQ(o.numMatched, 8u);
	// At every z: best threshold returns all 8, P = 0.75, R = 0.6, F1 = 2/3.
	for (double f : o.f1)
		EXPECT_DOUBLE_EQ(f, 2.0 / 3.0);
	EXPECT_DOUBLE_EQ(o.meanF1, 2.0 / 3.0);
	EXPECT_DOUBLE_EQ(o.recall, 0.6);
	// Known times 0.1 .. 0.6 and 0.7 (image 6 unknown): median 0.4.
	EXPECT_DOUBLE_EQ(o.medianTime, 0.4);
	EXPECT_DOUBLE_EQ(r.medianTime, 0.4);
	// The curve at z = 0.10 ends at (0.6, 0.75).
	const auto &curve = o.curves[5];
	ASSERT_EQ(curve.size(), 8u);
	EXPECT_DOUBLE_EQ(curve.back().recall, 0.6);
	EXPECT_DOUBLE_EQ(curve.back().precision, 0.75);
}

TEST(Evaluation, DuplicateInOneImageIsAFalsePositive)
{
	ObjectPoseError error(boxPoints(), PoseMetric::kAdd);
	std::map<int, EvalObject> objects = {{2, {70.0, &error}}};
	const Pose gt = poseAt(0, 0, 900);
	// Same correct pose twice: the second is unmatched.
	EvalReport r = evaluatePoses(objects, {{1, 4, 2, gt}},
				     {row(4, 2, 0.9, gt), row(4, 2, 0.3, gt)});
	const ObjectEvalResult &o = r.objects[0];
	EXPECT_EQ(o.numMatched, 1u);
	EXPECT_EQ(o.f1[5], 1.0); // threshold 0.9 returns only the first
	ASSERT_EQ(o.curves[5].size(), 2u);
	EXPECT_DOUBLE_EQ(o.curves[5][1].precision, 0.5);
	EXPECT_EQ(o.recall, 1.0);

	// Every estimate's outcome is reported: the first matched with no error.
	ASSERT_EQ(r.estimates.size(), 2u);
	EXPECT_TRUE(r.estimates[0].matched);
	EXPECT_DOUBLE_EQ(r.estimates[0].error, 0.0);
	EXPECT_EQ(r.estimates[0].imId, 4);
	EXPECT_FALSE(r.estimates[1].matched);

	// A wrong estimate scored above the right one takes the instance.
	Pose wrong = gt;
	wrong.t.z() += 50;
	r = evaluatePoses(objects, {{1, 4, 2, gt}}, {row(4, 2, 0.9, wrong), row(4, 2, 0.3, gt)});
	EXPECT_EQ(r.objects[0].f1[10], 0.0);
	EXPECT_EQ(r.objects[0].recall, 0.0);
	ASSERT_EQ(r.estimates.size(), 2u);
	EXPECT_TRUE(r.estimates[0].matched);
	EXPECT_NEAR(r.estimates[0].error, 50.0, 1e-9); // ADD of a translation is its length
}

TEST(Evaluation, EstimatesInOtherImagesAreFalsePositives)
{
	ObjectPoseError error(boxPoints(), PoseMetric::kAdd);
	std::map<int, EvalObject> objects = {{2, {70.0, &error}}};
	const Pose gt = poseAt(0, 0, 900);
	// Exact pose but for image 5, where object 2 is absent.
	EvalReport r = evaluatePoses(objects, {{1, 4, 2, gt}}, {row(5, 2, 0.9, gt)});
	EXPECT_EQ(r.objects[0].numMatched, 0u);
	EXPECT_EQ(r.objects[0].meanF1, 0.0);
}

TEST(Evaluation, SymmetricObjectUsesAdiAndMeansAverageObjects)
{
	// A square prism: 4-fold symmetric about z.
	std::vector<Eigen::Vector3f> square;
	for (float z : {-5.f, 5.f})
		for (auto [x, y] : {std::pair{20.f, 0.f}, {0.f, 20.f}, {-20.f, 0.f}, {0.f, -20.f}})
			square.push_back({x, y, z});
	ObjectPoseError adi(square, PoseMetric::kAdi);
	ObjectPoseError add(boxPoints(), PoseMetric::kAdd);
	std::map<int, EvalObject> objects = {{7, {40.0, &adi}}, {8, {70.0, &add}}};

	const Pose gt = poseAt(5, 5, 600);
	Pose turned = gt;
	turned.R = gt.R * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	EvalReport r = evaluatePoses(objects, {{1, 0, 7, gt}, {1, 0, 8, gt}},
				     {row(0, 7, 1.0, turned), row(0, 8, 1.0, turned, 0.25)});
	ASSERT_EQ(r.objects.size(), 2u);
	EXPECT_EQ(r.objects[0].objId, 7);
	EXPECT_EQ(r.objects[0].metric, PoseMetric::kAdi);
	EXPECT_EQ(r.objects[0].meanF1, 1.0);
	EXPECT_EQ(r.objects[0].medianTime, -1.0);
	EXPECT_EQ(r.objects[1].metric, PoseMetric::kAdd);
	EXPECT_EQ(r.objects[1].meanF1, 0.0); // the box is not 4-fold symmetric
	EXPECT_DOUBLE_EQ(r.meanF1, 0.5);
	EXPECT_DOUBLE_EQ(r.meanRecall, 0.5);
	EXPECT_DOUBLE_EQ(r.meanF1PerZ[0], 0.5);
	EXPECT_EQ(r.numGt, 2u);
	EXPECT_EQ(r.numEstimates, 2u);
	EXPECT_DOUBLE_EQ(r.medianTime, 0.25);
}

TEST(Evaluation, VisibleSurfaceRecallAveragesTheThresholdPairs)
{
	ObjectPoseError error(boxPoints(), PoseMetric::kAdd);
	const std::map<int, EvalObject> objects = {{3, {100.0, &error}}};
	const std::vector<EvalGt> gts = {{1, 1, 3, poseAt(0, 0, 700)},
					 {1, 1, 3, poseAt(200, 0, 700)},
					 {1, 2, 3, poseAt(0, 0, 700)}};
	const std::vector<ResultRow> estimates = {row(1, 3, 0.9, poseAt(0, 0, 700)),
						  row(1, 3, 0.8, poseAt(200, 0, 700)),
						  row(2, 3, 0.5, poseAt(0, 0, 700)),
						  row(3, 3, 0.4, poseAt(0, 0, 700))};
	VsdErrors vsd;
	vsd.tauShares = vsdTauShares();
	vsd.thetas = vsdThetas();
	const std::vector<double> steps = {1, 1, 1, 1, 1, 0, 0, 0, 0, 0};
	vsd.errors[{0, 0}] = std::vector<double>(10, 0.12);
	vsd.errors[{0, 1}] = std::vector<double>(10, 0.9);
	vsd.errors[{1, 0}] = std::vector<double>(10, 0.01); // taken by the higher score
	vsd.errors[{1, 1}] = std::vector<double>(10, 0.27);
	vsd.errors[{2, 2}] = steps;

	const EvalReport r = evaluatePoses(objects, gts, estimates, defaultZValues(), &vsd);
	ASSERT_EQ(r.estimates.size(), 4u);
	std::map<int, double> shareOfImage;
	for (const EstimateOutcome &e : r.estimates)
		shareOfImage[e.imId] += e.vsdShare;
	EXPECT_NEAR(shareOfImage[1], 0.8 + 0.5, 1e-12); // theta > 0.12: 8 of 10; > 0.27: 5
	EXPECT_NEAR(shareOfImage[2], 0.5, 1e-12);        // right at half the taus, every theta
	EXPECT_EQ(shareOfImage[3], 0.0);                 // no truth in the image
	ASSERT_EQ(r.objects.size(), 1u);
	EXPECT_NEAR(r.objects[0].arVsd, (0.8 + 0.5 + 0.5) / 3, 1e-12);
	EXPECT_NEAR(r.meanArVsd, (0.8 + 0.5 + 0.5) / 3, 1e-12);

	const EvalReport without = evaluatePoses(objects, gts, estimates);
	EXPECT_EQ(without.objects[0].arVsd, -1.0);
	EXPECT_EQ(without.meanArVsd, -1.0);
	EXPECT_EQ(without.estimates[0].vsdShare, -1.0);
}

TEST(Evaluation, ObjectWithoutDataAndMedian)
{
	ObjectPoseError error(boxPoints(), PoseMetric::kAdd);
	EvalReport r = evaluatePoses({{4, {70.0, &error}}}, {}, {});
	ASSERT_EQ(r.objects.size(), 1u);
	EXPECT_EQ(r.objects[0].numGt, 0u);
	EXPECT_EQ(r.objects[0].meanF1, 0.0);

	EXPECT_EQ(medianKnown({}), -1.0);
	EXPECT_EQ(medianKnown({-1, -1}), -1.0);
	EXPECT_EQ(medianKnown({3, -1, 1, 2}), 2.0);
	EXPECT_EQ(medianKnown({4, 1, 2, 3}), 2.5);
}

} // namespace
} // namespace ihf
