// SPDX-License-Identifier: MIT
#pragma once

// The median of a few hundred floats at most, exactly: the value
// std::nth_element puts at the middle (the (n / 2)-th smallest), found
// without its data-dependent branches. The view search takes one per
// rotation it tries (the depth residuals' median moves the model onto the
// observed surface), and on residuals nth_element's partition mispredicts
// about every other comparison: it was a quarter of the search's time.

#include <cstddef>
#include <span>

namespace ihf {

inline constexpr size_t kMaxMedianValues = 256;

// The (n / 2)-th smallest of v (n = v.size() <= kMaxMedianValues, finite
// values); v may be overwritten. Beyond kMaxMedianValues: nth_element.
float medianSelect(std::span<float> v);

} // namespace ihf
