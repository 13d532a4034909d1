// SPDX-License-Identifier: MIT
#pragma once

// The footprint of an object standing on the table: the oriented rectangle
// that bounds its vertical projection. Objects are placed so that footprints
// do not overlap, which keeps the scene free of interpenetration.

#include <array>

#include <Eigen/Core>

namespace ihf {

struct Footprint {
	Eigen::Vector2d centre = Eigen::Vector2d::Zero();
	Eigen::Vector2d halfSize = Eigen::Vector2d::Zero();
	double yaw = 0; // rotation of the rectangle's x axis about the table normal

	std::array<Eigen::Vector2d, 4> corners() const;
	Eigen::Vector2d axisX() const;
	Eigen::Vector2d axisY() const;
	// Radius of the circumscribed circle.
	double radius() const { return halfSize.norm(); }
	Footprint grown(double margin) const;
};

// Separating-axis test; footprints closer than gap count as overlapping.
bool footprintsOverlap(const Footprint &a, const Footprint &b, double gap = 0.0);

// Whether footprint f lies entirely inside the rectangle r.
bool footprintInside(const Footprint &f, const Footprint &r);

} // namespace ihf
