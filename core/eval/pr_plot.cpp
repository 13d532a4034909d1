// SPDX-License-Identifier: MIT
#include "core/eval/pr_plot.h"

#include "core/dataset/bop_io.h"

#ifdef IHF_HAVE_CAIRO
#include <algorithm>
#include <cstdio>
#include <string>

#include <cairo.h>

#include "core/eval/eval_report_json.h"
#endif

namespace ihf {

#ifndef IHF_HAVE_CAIRO

bool prPlotSupported()
{
	return false;
}

Expected<RgbImage> renderPrPlot(const EvalReport &)
{
	return makeError(Errc::kUnsupported, "built without plotting support (libcairo2-dev)");
}

#else

bool prPlotSupported()
{
	return true;
}

namespace {

struct Rgb {
	double r, g, b;
};

// Matplotlib's "tab10" then "Dark2": distinct, readable on white.
constexpr Rgb kPalette[] = {
	{0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.173, 0.627, 0.173},
	{0.839, 0.153, 0.157}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
	{0.890, 0.467, 0.761}, {0.498, 0.498, 0.498}, {0.737, 0.741, 0.133},
	{0.090, 0.745, 0.812}, {0.106, 0.620, 0.467}, {0.851, 0.373, 0.008},
	{0.459, 0.439, 0.702}, {0.906, 0.161, 0.541}, {0.400, 0.651, 0.118},
	{0.902, 0.671, 0.008},
};
constexpr size_t kNumColours = sizeof(kPalette) / sizeof(kPalette[0]);

constexpr double kPanelSize = 380;  // plot area, pixels
constexpr double kMarginLeft = 70;
constexpr double kMarginTop = 50;
constexpr double kMarginBottom = 60;
constexpr double kPanelGap = 80;
constexpr double kLegendWidth = 250;

void setColour(cairo_t *cr, const Rgb &c)
{
	cairo_set_source_rgb(cr, c.r, c.g, c.b);
}

void textAt(cairo_t *cr, const std::string &text, double x, double y, double alignX,
	    double alignY)
{
	cairo_text_extents_t ext;
	cairo_text_extents(cr, text.c_str(), &ext);
	cairo_move_to(cr, x - ext.x_bearing - alignX * ext.width,
		      y - ext.y_bearing - alignY * ext.height);
	cairo_show_text(cr, text.c_str());
}

std::string fmt(const char *format, double v)
{
	char buf[64];
	std::snprintf(buf, sizeof(buf), format, v);
	return buf;
}

// One panel: axes box, grid, ticks, labels and every object's curve.
void drawPanel(cairo_t *cr, const EvalReport &report, size_t zi, double x0, double y0)
{
	const double s = kPanelSize;
	auto px = [&](double recall) { return x0 + recall * s; };
	auto py = [&](double precision) { return y0 + (1.0 - precision) * s; };

	// Grid and ticks every 0.2.
	cairo_set_font_size(cr, 13);
	for (int i = 0; i <= 5; ++i) {
		const double v = i * 0.2;
		cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
		cairo_set_line_width(cr, 1);
		cairo_move_to(cr, px(v), y0);
		cairo_line_to(cr, px(v), y0 + s);
		cairo_move_to(cr, x0, py(v));
		cairo_line_to(cr, x0 + s, py(v));
		cairo_stroke(cr);

		cairo_set_source_rgb(cr, 0, 0, 0);
		cairo_move_to(cr, px(v), y0 + s);
		cairo_line_to(cr, px(v), y0 + s + 5);
		cairo_move_to(cr, x0, py(v));
		cairo_line_to(cr, x0 - 5, py(v));
		cairo_stroke(cr);
		textAt(cr, fmt("%.1f", v), px(v), y0 + s + 9, 0.5, 0);
		textAt(cr, fmt("%.1f", v), x0 - 9, py(v), 1, 0.5);
	}
	cairo_set_source_rgb(cr, 0, 0, 0);
	cairo_set_line_width(cr, 1.5);
	cairo_rectangle(cr, x0, y0, s, s);
	cairo_stroke(cr);

	cairo_set_font_size(cr, 15);
	textAt(cr, "Recall", x0 + s / 2, y0 + s + 32, 0.5, 0);
	cairo_save(cr);
	cairo_move_to(cr, 0, 0);
	cairo_translate(cr, x0 - 48, y0 + s / 2);
	cairo_rotate(cr, -M_PI / 2);
	textAt(cr, "Precision", 0, 0, 0.5, 0.5);
	cairo_restore(cr);

	cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
	cairo_set_font_size(cr, 16);
	std::string title = fmt("z = %.2f", report.zValues[zi]);
	if (zi < report.meanF1PerZ.size())
		title += fmt(",  mean F1 %.3f", report.meanF1PerZ[zi]);
	textAt(cr, title, x0 + s / 2, y0 - 30, 0.5, 0);
	cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

	// Curves, clipped to the axes (with room for markers on the border).
	cairo_save(cr);
	cairo_rectangle(cr, x0 - 6, y0 - 6, s + 12, s + 12);
	cairo_clip(cr);
	for (size_t k = 0; k < report.objects.size(); ++k) {
		const std::vector<PrPoint> &curve = report.objects[k].curves[zi];
		if (curve.empty())
			continue;
		setColour(cr, kPalette[k % kNumColours]);
		cairo_set_line_width(cr, 2.2);
		cairo_move_to(cr, px(curve[0].recall), py(curve[0].precision));
		for (const PrPoint &p : curve)
			cairo_line_to(cr, px(p.recall), py(p.precision));
		cairo_stroke(cr);
		if (curve.size() <= 40) {
			for (const PrPoint &p : curve) {
				cairo_arc(cr, px(p.recall), py(p.precision), 3.5, 0, 2 * M_PI);
				cairo_fill(cr);
			}
		}
	}
	cairo_restore(cr);
}

void drawLegend(cairo_t *cr, const EvalReport &report, double x0, double y0)
{
	cairo_set_source_rgb(cr, 0, 0, 0);
	cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
	cairo_set_font_size(cr, 14);
	textAt(cr, "object (metric): mean F1", x0, y0, 0, 0);
	cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
	cairo_set_font_size(cr, 14);
	double y = y0 + 28;
	for (size_t k = 0; k < report.objects.size(); ++k) {
		const ObjectEvalResult &r = report.objects[k];
		setColour(cr, kPalette[k % kNumColours]);
		cairo_set_line_width(cr, 3);
		cairo_move_to(cr, x0, y + 8);
		cairo_line_to(cr, x0 + 28, y + 8);
		cairo_stroke(cr);
		cairo_set_source_rgb(cr, 0, 0, 0);
		char buf[96];
		std::snprintf(buf, sizeof(buf), "obj %d (%s): %.3f", r.objId, poseMetricName(r.metric),
			      r.meanF1);
		textAt(cr, buf, x0 + 36, y + 8, 0, 0.5);
		y += 24;
	}
	char buf[96];
	std::snprintf(buf, sizeof(buf), "mean over objects: %.3f", report.meanF1);
	textAt(cr, buf, x0, y + 10, 0, 0);
	cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
	cairo_set_font_size(cr, 12);
	textAt(cr, "correct: error <= z * diameter", x0, y + 36, 0, 0);
	textAt(cr, "mean F1: average over z = 0.05..0.15", x0, y + 54, 0, 0);
}

} // namespace

Expected<RgbImage> renderPrPlot(const EvalReport &report)
{
	std::vector<size_t> panels;
	for (double z : {0.05, 0.10, 0.15}) {
		const int i = curveZIndex(report, z);
		if (i >= 0)
			panels.push_back(static_cast<size_t>(i));
	}
	if (panels.empty())
		return makeError(Errc::kInvalidArgument,
				 "PR plot: the report has none of z = 0.05, 0.10, 0.15");

	const double legendHeight = 110 + 24.0 * static_cast<double>(report.objects.size());
	RgbImage image;
	image.width = static_cast<int>(kMarginLeft +
				       panels.size() * (kPanelSize + kPanelGap) + kLegendWidth);
	image.height = static_cast<int>(
		std::max(kMarginTop + kPanelSize + kMarginBottom, kMarginTop + legendHeight));

	cairo_surface_t *surface =
		cairo_image_surface_create(CAIRO_FORMAT_RGB24, image.width, image.height);
	if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
		cairo_surface_destroy(surface);
		return makeError(Errc::kCapacity, "PR plot: cannot create the drawing surface");
	}
	cairo_t *cr = cairo_create(surface);
	cairo_set_source_rgb(cr, 1, 1, 1);
	cairo_paint(cr);
	cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

	for (size_t p = 0; p < panels.size(); ++p)
		drawPanel(cr, report, panels[p], kMarginLeft + p * (kPanelSize + kPanelGap),
			  kMarginTop);
	drawLegend(cr, report, kMarginLeft + panels.size() * (kPanelSize + kPanelGap) - 30,
		   kMarginTop);

	const cairo_status_t status = cairo_status(cr);
	cairo_destroy(cr);
	cairo_surface_flush(surface);
	if (status != CAIRO_STATUS_SUCCESS) {
		cairo_surface_destroy(surface);
		return makeError(Errc::kIo, std::string("PR plot: drawing failed: ") +
						    cairo_status_to_string(status));
	}

	// RGB24 keeps each pixel in a native-endian 32-bit word, 0x00RRGGBB.
	const unsigned char *data = cairo_image_surface_get_data(surface);
	const int stride = cairo_image_surface_get_stride(surface);
	image.pixels.resize(static_cast<size_t>(image.width) * image.height * 3);
	for (int y = 0; y < image.height; ++y) {
		const auto *row = reinterpret_cast<const uint32_t *>(data + static_cast<size_t>(y) * stride);
		uint8_t *out = image.pixels.data() + static_cast<size_t>(y) * image.width * 3;
		for (int x = 0; x < image.width; ++x) {
			out[3 * x + 0] = static_cast<uint8_t>(row[x] >> 16);
			out[3 * x + 1] = static_cast<uint8_t>(row[x] >> 8);
			out[3 * x + 2] = static_cast<uint8_t>(row[x]);
		}
	}
	cairo_surface_destroy(surface);
	return image;
}

#endif

Status writePrPlot(const std::filesystem::path &file, const EvalReport &report)
{
	Expected<RgbImage> image = renderPrPlot(report);
	if (!image)
		return image.error();
	return writePng8(file, image->width, image->height, 3, image->pixels.data());
}

} // namespace ihf
