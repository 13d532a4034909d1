// SPDX-License-Identifier: MIT
#include "core/synth/detection_box.h"

#include <algorithm>
#include <cmath>

namespace ihf {

namespace {

double round1(double v) { return std::round(v * 10.0) / 10.0; }

} // namespace

Detection coarseDetection(const std::array<int, 4> &bboxObj, int imageWidth, int imageHeight,
			  int sceneId, int imageId, int objId, SynthRandom &rng,
			  const DetectionNoise &noise)
{
	Detection d;
	d.sceneId = sceneId;
	d.imageId = imageId;
	d.categoryId = objId;
	const double w = std::max(bboxObj[2], 1), h = std::max(bboxObj[3], 1);
	const double gw = rng.uniform(noise.growMin, noise.growMax);
	const double gh = rng.uniform(noise.growMin, noise.growMax);
	const double sx = rng.uniform(-noise.shiftMax, noise.shiftMax);
	const double sy = rng.uniform(-noise.shiftMax, noise.shiftMax);
	const double cx = bboxObj[0] + 0.5 * w + sx * w;
	const double cy = bboxObj[1] + 0.5 * h + sy * h;
	const double hw = 0.5 * w * (1 + gw), hh = 0.5 * h * (1 + gh);
	const double x0 = std::clamp(cx - hw, 0.0, static_cast<double>(imageWidth));
	const double x1 = std::clamp(cx + hw, 0.0, static_cast<double>(imageWidth));
	const double y0 = std::clamp(cy - hh, 0.0, static_cast<double>(imageHeight));
	const double y1 = std::clamp(cy + hh, 0.0, static_cast<double>(imageHeight));
	d.bbox = {round1(x0), round1(y0), round1(x1 - x0), round1(y1 - y0)};
	d.score = std::round(rng.uniform(noise.scoreMin, noise.scoreMax) * 1000.0) / 1000.0;
	d.time = 0.0;
	return d;
}

} // namespace ihf
