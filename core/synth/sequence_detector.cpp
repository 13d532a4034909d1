// SPDX-License-Identifier: MIT
#include "core/synth/sequence_detector.h"

#include <algorithm>

namespace ihf {

std::vector<uint8_t> detectorMisses(int frames, const DetectorParams &p, SynthRandom &rng)
{
	std::vector<uint8_t> missed(static_cast<size_t>(std::max(frames, 0)), 0);
	const double m = std::clamp(p.missProbability, 0.0, 1.0);
	if (m <= 0.0)
		return missed;
	if (m >= 1.0) {
		std::fill(missed.begin(), missed.end(), 1);
		return missed;
	}
	const double stay = std::clamp(p.missPersistence, 0.0, 0.99);
	// Stationary share of the miss state: start / (start + 1 - stay) = m.
	const double start = std::min(1.0, m * (1.0 - stay) / (1.0 - m));
	bool miss = rng.chance(m);
	for (int f = 0; f < frames; ++f) {
		if (f > 0)
			miss = rng.chance(miss ? stay : start);
		missed[static_cast<size_t>(f)] = miss ? 1 : 0;
	}
	return missed;
}

std::optional<Detection> detectObject(const GtInfo &info, bool missed, int imageWidth,
				      int imageHeight, int sceneId, int imageId, int objId,
				      SynthRandom &rng, const DetectorParams &params)
{
	if (missed || info.pxCountVisib <= 0 || info.visibFract < params.minVisibFract)
		return std::nullopt;
	return coarseDetection(info.bboxObj, imageWidth, imageHeight, sceneId, imageId, objId, rng,
			       params.noise);
}

} // namespace ihf
