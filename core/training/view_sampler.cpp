// SPDX-License-Identifier: MIT
#include "core/training/view_sampler.h"

#include <cmath>
#include <random>

#include "core/geometry/rotation.h"

namespace ihf {

std::vector<TrainingView> sampleTrainingViews(const ViewSamplerConfig &config)
{
	std::vector<TrainingView> views;
	std::mt19937_64 rng(config.seed);
	auto uniform01 = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };

	const double sinMin = std::sin(config.minElevationDeg * M_PI / 180.0);
	const double sinMax = std::sin(config.maxElevationDeg * M_PI / 180.0);
	const auto dirs = fibonacciSphere(config.viewpoints);
	int vp = 0;
	for (const auto &d : dirs) {
		if (d.z() < sinMin - 1e-9 || d.z() > sinMax + 1e-9)
			continue;
		// A random phase per direction decorrelates in-plane samples.
		const double phase = uniform01() * 2.0 * M_PI / std::max(1, config.inplaneSteps);
		for (int k = 0; k < std::max(1, config.inplaneSteps); ++k) {
			TrainingView v;
			double roll = phase + 2.0 * M_PI * k / std::max(1, config.inplaneSteps);
			v.pose.R = lookAtRotation(d, roll);
			double dist = config.minDistance +
				      uniform01() * (config.maxDistance - config.minDistance);
			v.pose.t = Eigen::Vector3d(0, 0, dist);
			v.viewpoint = vp;
			v.inplane = k;
			views.push_back(v);
		}
		++vp;
	}
	return views;
}

} // namespace ihf
