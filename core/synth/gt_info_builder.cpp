// SPDX-License-Identifier: MIT
#include "core/synth/gt_info_builder.h"

#include <algorithm>
#include <limits>

namespace ihf {

GtInfo buildGtInfo(const ObjectSilhouette &silhouette, ImageView<const uint16_t> label,
		   uint16_t targetLabel, const DepthImage16 &sensorDepth)
{
	GtInfo info;
	info.bboxObj = silhouette.bbox;
	info.pxCountAll = silhouette.pxCountAll;
	int x0 = std::numeric_limits<int>::max(), y0 = x0, x1 = -x0, y1 = -x0;
	for (int y = 0; y < label.height; ++y) {
		for (int x = 0; x < label.width; ++x) {
			if (silhouette.at(x, y) > 0.0f && sensorDepth.at(x, y) > 0)
				++info.pxCountValid;
			if (label.at(x, y) != targetLabel)
				continue;
			++info.pxCountVisib;
			x0 = std::min(x0, x);
			x1 = std::max(x1, x);
			y0 = std::min(y0, y);
			y1 = std::max(y1, y);
		}
	}
	if (info.pxCountVisib > 0)
		info.bboxVisib = {x0, y0, x1 - x0, y1 - y0};
	info.visibFract = info.pxCountAll > 0
				  ? static_cast<double>(info.pxCountVisib) / info.pxCountAll
				  : 0.0;
	return info;
}

} // namespace ihf
