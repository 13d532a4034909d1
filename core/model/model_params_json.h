// SPDX-License-Identifier: MIT
#pragma once

// JSON text of ModelParams, as stored in the PARAMS section of a forest file
// and printed by `ihf forest info`. Keys are snake_case, enums are strings
// ("count", "variable", "conjugate_gradient", ...). Floats are written in
// their shortest exact form, so a round trip is bit-exact. Reading is
// strict: every field must be present with the right type and no unknown
// key is accepted, because inference must use exactly the training settings;
// a mismatch means the file came from a different writer (bump the format
// version instead of relaxing this).

#include <string>
#include <string_view>

#include "core/common/expected.h"
#include "core/model/model_params.h"

namespace ihf {

// Pretty-printed JSON (two-space indent). Fails, naming the field, on a
// non-finite number (JSON cannot hold one).
Expected<std::string> modelParamsToJson(const ModelParams &params);

// Parses text; errors start with source (e.g. "obj.ihf: PARAMS") and name
// the field, e.g. "obj.ihf: PARAMS: hocp.weighting: unknown value "x"
// (expected one of count, abs_weight, sign_split)".
Expected<ModelParams> modelParamsFromJson(std::string_view text, std::string_view source);

} // namespace ihf
