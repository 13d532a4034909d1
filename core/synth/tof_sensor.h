// SPDX-License-Identifier: MIT
#pragma once

// A continuous-wave time-of-flight depth sensor model (Kinect v2, Azure
// Kinect, pmd) applied to a clean rendered depth image. It fails in other
// places than the structured-light model (kinect_sensor.h), which is why a
// second benchmark made with it says something the first cannot:
//  1. no projector shadows and no lateral jitter: the illumination sits
//     beside the lens and every pixel measures on its own;
//  2. mixed ("flying") pixels: a pixel whose footprint straddles a depth
//     edge sums both surfaces' returns, weighted by coverage and by their
//     brightness (1 / z^2), and reports a depth between them; the camera's
//     own filter invalidates part of them, the rest stay, floating in the
//     air between object and background;
//  3. axial noise from photon shot noise: sigma = sigma_ref (z / z_ref) /
//     sqrt(cos theta), white per pixel (Foix, Alenya, Torras 2011;
//     Tolle et al. 2019 measure ~1-2 mm at 1 m on a white target);
//  4. a systematic "wiggling" error, periodic in distance, that calibration
//     leaves at a millimetre or two;
//  5. missing depth where the returned amplitude cos(theta) (z_ref/z)^2 is
//     too low (grazing incidence, far), on dark or shiny patches (the
//     scene's per-label dropout, in blobs), at random pixels, and outside
//     the 0.5-3.86 m range (Azure Kinect NFOV unbinned).
// Multipath (concave corners measured too far) is not modelled.

#include <cstdint>

#include "core/common/image.h"
#include "core/geometry/camera_intrinsics.h"
#include "core/synth/kinect_sensor.h"
#include "core/synth/synth_random.h"

namespace ihf {

struct TofParams {
	// Shot noise at the reference distance, normal incidence.
	double sigmaRefMm = 1.5;
	double zRefMm = 1000.0;
	double minCosine = 0.1; // the noise stops growing at grazing angles
	// Wiggling: amplitude (mm) and period (mm of distance).
	double wiggleMm = 1.0;
	double wigglePeriodMm = 1250.0;
	// Mixed pixels at edges (a neighbour farther than max(jump, rel z)).
	double edgeJumpMm = 15.0;
	double edgeJumpRel = 0.02;
	double flyingInvalid = 0.5;  // share the camera's filter removes
	double ownCoverageMin = 0.5; // the pixel centre lies on its own surface
	// Amplitude invalidation: cos(theta) (z_ref / z)^2 below this.
	double minAmplitude = 0.06;
	double amplitudeSoft = 0.04; // dropout ramps up over this span above it
	double pixelDropout = 0.0005;
	double minRangeMm = 500.0;
	double maxRangeMm = 3860.0;
};

// Axial standard deviation (mm) at depth zMm and incidence theta (radians).
double tofAxialSigmaMm(const TofParams &p, double zMm, double theta);

// The depth a pixel reports when it sees the surfaces at zOwn (share
// coverage of its footprint) and zOther (the rest): amplitude-weighted.
double tofMixedDepth(double zOwn, double zOther, double coverage);

// Sensor depth in units of depthScale mm (0 = no depth). Uses the scene's
// depth, labels and per-label dropout (dark materials); the projector view
// is not used.
DepthImage16 simulateTof(const SensorScene &scene, const CameraIntrinsics &K, const TofParams &p,
			 SynthRandom &rng, double depthScale = 1.0);

} // namespace ihf
