// SPDX-License-Identifier: MIT
#include "core/synth/table_footprint.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ihf {

Eigen::Vector2d Footprint::axisX() const
{
	return {std::cos(yaw), std::sin(yaw)};
}

Eigen::Vector2d Footprint::axisY() const
{
	return {-std::sin(yaw), std::cos(yaw)};
}

std::array<Eigen::Vector2d, 4> Footprint::corners() const
{
	const Eigen::Vector2d ax = axisX() * halfSize.x(), ay = axisY() * halfSize.y();
	return {centre - ax - ay, centre + ax - ay, centre + ax + ay, centre - ax + ay};
}

Footprint Footprint::grown(double margin) const
{
	Footprint f = *this;
	f.halfSize += Eigen::Vector2d::Constant(margin);
	return f;
}

namespace {

void projectOn(const Footprint &f, const Eigen::Vector2d &axis, double &lo, double &hi)
{
	lo = std::numeric_limits<double>::max();
	hi = -lo;
	for (const auto &c : f.corners()) {
		const double p = c.dot(axis);
		lo = std::min(lo, p);
		hi = std::max(hi, p);
	}
}

} // namespace

bool footprintsOverlap(const Footprint &a, const Footprint &b, double gap)
{
	const Footprint ga = a.grown(gap / 2), gb = b.grown(gap / 2);
	for (const Eigen::Vector2d &axis : {ga.axisX(), ga.axisY(), gb.axisX(), gb.axisY()}) {
		double alo, ahi, blo, bhi;
		projectOn(ga, axis, alo, ahi);
		projectOn(gb, axis, blo, bhi);
		if (ahi < blo || bhi < alo)
			return false;
	}
	return true;
}

bool footprintInside(const Footprint &f, const Footprint &r)
{
	for (const auto &c : f.corners()) {
		const Eigen::Vector2d d = c - r.centre;
		if (std::abs(d.dot(r.axisX())) > r.halfSize.x() ||
		    std::abs(d.dot(r.axisY())) > r.halfSize.y())
			return false;
	}
	return true;
}

} // namespace ihf
