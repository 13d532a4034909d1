// SPDX-License-Identifier: MIT
#pragma once

// Procedural objects of the paper's kind: shapes that are nearly symmetric
// and told apart by a small part (a cup's handle, a camera's lens and strap
// lug, a bottle's pump nozzle). Deterministic closed meshes in millimetres,
// modelled z-up standing on z = 0, for benchmarks beside the LM-O meshes.

#include <optional>
#include <span>
#include <string_view>

#include "core/geometry/mesh.h"

namespace ihf {

enum class HouseholdObject { kCup, kCamera, kBottle };

// Each object with its small part, or without it (withPart false: the body
// alone, to tell where the part shows in a view).

// A coffee cup: a hollow tapered body about +z (outer radius 36 mm at the
// foot, 42 at the rim, 95 high, 4 mm walls) and a handle on its +x side.
Mesh makeCup(bool withPart = true);

// A camera: a 124 x 68 x 82 mm body, a lens (radius 33, 46 long) out of its
// -y face off centre towards +x, a strap lug on top at -x and a shutter
// button at +x (the part: lens, lug and button).
Mesh makeCamera(bool withPart = true);

// A shampoo bottle: an oval body (96 x 56 mm, 184 high) with shoulders and
// a neck, a pump on top and its nozzle pointing +x (the part: the nozzle).
Mesh makeBottle(bool withPart = true);

Mesh makeHouseholdObject(HouseholdObject object, bool withPart = true);

// "cup", "camera", "bottle".
std::optional<HouseholdObject> householdObjectNamed(std::string_view name);
std::string_view householdObjectName(HouseholdObject object);
std::span<const HouseholdObject> householdObjects();

} // namespace ihf
