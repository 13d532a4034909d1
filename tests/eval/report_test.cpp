// SPDX-License-Identifier: MIT
// The report's table, JSON and precision-recall plot.

#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/eval/eval_report_json.h"
#include "core/eval/eval_report_text.h"
#include "core/eval/pr_plot.h"
#include "tests/common/test_paths.h"

namespace ihf {
namespace {

// Two objects with known F1 values and a curve at z = 0.10.
EvalReport sampleReport()
{
	EvalReport r;
	r.zValues = defaultZValues();
	for (int k = 0; k < 2; ++k) {
		ObjectEvalResult o;
		o.objId = k ? 11 : 1;
		o.metric = k ? PoseMetric::kAdi : PoseMetric::kAdd;
		o.diameter = k ? 175.889 : 102.099;
		o.numGt = 4;
		o.numEstimates = 5;
		o.numMatched = 4;
		for (size_t i = 0; i < r.zValues.size(); ++i) {
			o.f1.push_back(k ? 0.5 : 0.25 + 0.05 * i);
			if (k)
				o.curves.push_back({{0.9, 0.5, 0.25, 1 / 3.0}, {0.5, 0.3, 0.75, 0.45}});
			else
				o.curves.push_back({{0.9, 1.0, 0.25, 0.4}, {0.5, 0.6, 0.75, 0.6667}});
		}
		o.meanF1 = k ? 0.5 : 0.5;
		o.recall = k ? 0.75 : 0.5;
		o.medianTime = k ? -1 : 0.125;
		r.objects.push_back(o);
	}
	r.meanF1PerZ.assign(r.zValues.size(), 0.5);
	r.meanF1 = 0.5;
	r.meanRecall = 0.625;
	r.medianTime = 0.125;
	r.numGt = 8;
	r.numEstimates = 10;
	return r;
}

TEST(EvalReport, TableListsEveryObjectAndTheMean)
{
	const std::string text = formatEvalTable(sampleReport());
	EXPECT_NE(text.find("meanF1"), std::string::npos);
	EXPECT_NE(text.find("   1 ADD      102.10     4     5 0.250 0.300"), std::string::npos) << text;
	EXPECT_NE(text.find("  11 ADI      175.89"), std::string::npos) << text;
	EXPECT_NE(text.find("mean"), std::string::npos);
	EXPECT_NE(text.find("0.6250"), std::string::npos);
}

TEST(EvalReport, JsonHoldsEverything)
{
	const auto dir = test::freshTempDir("eval_report_json");
	const auto file = dir / "report.json";
	ASSERT_TRUE(writeEvalReportJson(file, sampleReport()).ok());
	std::ifstream in(file);
	const auto doc = nlohmann::json::parse(in);
	ASSERT_EQ(doc["z_values"].size(), 11u);
	ASSERT_EQ(doc["objects"].size(), 2u);
	const auto &o = doc["objects"][0];
	EXPECT_EQ(o["obj_id"], 1);
	EXPECT_EQ(o["metric"], "ADD");
	EXPECT_DOUBLE_EQ(o["f1"][1].get<double>(), 0.30);
	EXPECT_EQ(o["num_gt"], 4);
	EXPECT_DOUBLE_EQ(o["median_time"].get<double>(), 0.125);
	EXPECT_TRUE(doc["objects"][1]["median_time"].is_null());
	EXPECT_EQ(doc["objects"][1]["metric"], "ADI");
	ASSERT_EQ(o["pr_curve_z0.10"].size(), 2u);
	EXPECT_DOUBLE_EQ(o["pr_curve_z0.10"][1]["recall"].get<double>(), 0.75);
	EXPECT_DOUBLE_EQ(doc["mean"]["recall_0.1d"].get<double>(), 0.625);
	EXPECT_EQ(doc["mean"]["num_estimates"], 10);
	// Nothing but the report is left in the folder.
	EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
				std::filesystem::directory_iterator()),
		  1);
	// An unwritable place (a folder that is a file) is an error naming the
	// file; a missing folder is created, as by the other writers.
	std::ofstream(dir / "blocker") << "keep";
	Status bad = writeEvalReportJson(dir / "blocker" / "r.json", sampleReport());
	ASSERT_FALSE(bad.ok());
	EXPECT_NE(bad.error().message.find("r.json"), std::string::npos);
	EXPECT_TRUE(writeEvalReportJson(dir / "new_dir" / "r.json", sampleReport()).ok());
}

TEST(EvalReport, PlotDrawsColouredCurves)
{
	if (!prPlotSupported()) {
		Expected<RgbImage> img = renderPrPlot(sampleReport());
		ASSERT_FALSE(img.ok());
		EXPECT_NE(img.error().message.find("libcairo2-dev"), std::string::npos);
		GTEST_SKIP() << "built without cairo";
	}
	Expected<RgbImage> img = renderPrPlot(sampleReport());
	ASSERT_TRUE(img.ok()) << img.error().message;
	ASSERT_GT(img->width, 800);
	ASSERT_GT(img->height, 300);
	ASSERT_EQ(img->pixels.size(), size_t(img->width) * img->height * 3);
	// The first object's colour (tab10 blue, 31,119,180) and the second's
	// (orange, 255,127,14) are drawn.
	size_t blue = 0, orange = 0, white = 0;
	for (size_t i = 0; i < img->pixels.size(); i += 3) {
		const int r = img->pixels[i], g = img->pixels[i + 1], b = img->pixels[i + 2];
		blue += std::abs(r - 31) + std::abs(g - 119) + std::abs(b - 180) < 12;
		orange += std::abs(r - 255) + std::abs(g - 127) + std::abs(b - 14) < 12;
		white += r == 255 && g == 255 && b == 255;
	}
	EXPECT_GT(blue, 200u);
	EXPECT_GT(orange, 200u);
	EXPECT_GT(white, img->pixels.size() / 3 / 2);
}

} // namespace
} // namespace ihf
