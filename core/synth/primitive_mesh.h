// SPDX-License-Identifier: MIT
#pragma once

// Procedural meshes for clutter, occluders and the room: boxes, cylinders,
// spheres and flat quads, in millimetres with outward vertex normals. The
// solids are built standing on z = 0 (their resting frame), centred in x, y.

#include "core/geometry/mesh.h"

namespace ihf {

// Axis-aligned box of size sx x sy x sz, bottom face on z = 0.
Mesh makeBox(double sx, double sy, double sz);

// Upright cylinder of the given radius and height on z = 0, closed by caps.
Mesh makeCylinder(double radius, double height, int segments = 32);

// Cylinder lying on its side along x, touching z = 0.
Mesh makeLyingCylinder(double radius, double length, int segments = 32);

// Sphere of the given radius touching z = 0.
Mesh makeSphere(double radius, int rings = 12, int segments = 24);

// Rectangle [-sx/2, sx/2] x [-sy/2, sy/2] in the plane z = 0, normal +z.
Mesh makeQuad(double sx, double sy);

} // namespace ihf
