// SPDX-License-Identifier: MIT
#pragma once

// A lighter copy of a mesh for rendering hypotheses. The LINEMOD meshes
// have triangles of 1-2 mm (the can: 45,666 faces), about a pixel at 1 m,
// so the renderer spends its time on per-triangle set-up; collapsing edges
// while the surface moves by at most maxErrorMm (meshoptimizer's quadric
// simplifier) keeps the rendered depth within that bound for a fraction of
// the triangles. Offline (allocates): at model load.

#include "core/common/expected.h"
#include "core/geometry/mesh.h"

namespace ihf {

struct SimplifiedMesh {
	Mesh mesh;
	float errorMm = 0; // the simplifier's own estimate of the deviation
};

// maxErrorMm > 0. Normals, when the input has them, follow their vertices.
Expected<SimplifiedMesh> simplifyMesh(const Mesh &mesh, float maxErrorMm);

} // namespace ihf
