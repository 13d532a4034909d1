// SPDX-License-Identifier: MIT
#pragma once

// BOP scene_gt_info entries from the renders, as bop_toolkit's calc_gt_info
// defines them: bbox_obj and px_count_all over the whole silhouette (also
// outside the image), px_count_valid = silhouette pixels in the image with
// sensor depth, px_count_visib / bbox_visib from the scene's label buffer
// (the visible part of the target), visib_fract = px_count_visib /
// px_count_all. Boxes are x, y, w, h with w = xmax - xmin.

#include "core/common/image.h"
#include "core/dataset/bop_types.h"
#include "core/synth/scene_render.h"

namespace ihf {

GtInfo buildGtInfo(const ObjectSilhouette &silhouette, ImageView<const uint16_t> label,
		   uint16_t targetLabel, const DepthImage16 &sensorDepth);

} // namespace ihf
