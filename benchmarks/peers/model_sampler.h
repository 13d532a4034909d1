// SPDX-License-Identifier: MIT
#pragma once

// Uniform random points on a mesh's surface (area weighted), each with the
// face's outward normal: the model cloud every peer starts from.

#include <cstdint>

#include "benchmarks/peers/peer.h"
#include "core/common/expected.h"
#include "core/geometry/mesh.h"

namespace ihf::peers {

Expected<PeerModel> sampleModel(const Mesh &mesh, int objId, double diameter, int count,
				uint32_t seed);

} // namespace ihf::peers
