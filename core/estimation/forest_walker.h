// SPDX-License-Identifier: MIT
#pragma once

// Passes one test part down every tree of a forest and casts the votes of
// the leaves it reaches (paper Sect. III-C): at each split node the part's
// control points are depth-checked against the node template's range,
// histogrammed, and compared with the template. The forest was validated at
// load, so the walk needs no bounds checks.

#include <span>

#include "core/features/hocp.h"
#include "core/features/part.h"
#include "core/forest/forest_view.h"
#include "core/pose/vote_modes.h"

namespace ihf {

// L2 distance between a histogram and template `index` of a tree.
float templateDistance(const ForestView &forest, const TreeView &tree, uint32_t index,
		       std::span<const float> histogram);

// Histograms castPartVotes() can keep along a part's walk.
inline constexpr size_t kMaxHistogramSlots = 32;

// Appends the part's votes to votes[count...]; returns the new count (never
// more than votes.size()). hist is scratch of forest.dims floats, or k times
// that (2 <= k <= kMaxHistogramSlots) to keep k histograms along the walk
// and reuse them (the same votes, faster). Each vote weighs
// 1 / (leaf size * trees), so every part carries the same mass.
size_t castPartVotes(const ForestView &forest, std::span<const PartCp> cps,
		     const Eigen::Vector3f &centreMm, const HocpConfig &hocp, float marginMm,
		     std::span<float> hist, std::span<CastVote> votes, size_t count);

} // namespace ihf
