// SPDX-License-Identifier: MIT
#include "core/synth/object_schedule.h"

#include <algorithm>

#include <Eigen/Geometry>

namespace ihf {

namespace {

// Rest-to-rest ease: zero velocity and acceleration at both ends.
double ease(double s)
{
	s = std::clamp(s, 0.0, 1.0);
	return s * s * s * (10 - 15 * s + 6 * s * s);
}

} // namespace

Pose carryPose(const Carry &c, double u)
{
	const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
	constexpr double kLift = 0.25, kLower = 0.75; // phase boundaries
	Pose p;
	if (u < kLift) {
		p.R = c.from.R;
		p.t = c.from.t + ease(u / kLift) * c.liftFrom * up;
	} else if (u < kLower) {
		const double s = ease((u - kLift) / (kLower - kLift));
		const Eigen::Quaterniond a(c.from.R), b(c.to.R);
		p.R = a.slerp(s, b).toRotationMatrix();
		p.t = (1 - s) * (c.from.t + c.liftFrom * up) + s * (c.to.t + c.liftTo * up);
	} else {
		p.R = c.to.R;
		p.t = c.to.t + (1 - ease((u - kLower) / (1 - kLower))) * c.liftTo * up;
	}
	return p;
}

bool ObjectSchedule::present(double t) const
{
	if (carries_.empty())
		return true;
	if (carries_.front().kind == CarryKind::kPutDown && t < carries_.front().start)
		return false;
	if (carries_.back().kind == CarryKind::kTakeAway && t >= carries_.back().end)
		return false;
	return true;
}

Pose ObjectSchedule::modelToWorld(double t) const
{
	Pose pose = initial_;
	for (const Carry &c : carries_) {
		if (t < c.start)
			break;
		if (t >= c.end) {
			pose = c.to;
			continue;
		}
		return carryPose(c, (t - c.start) / (c.end - c.start));
	}
	return pose;
}

bool ObjectSchedule::resting(double t) const
{
	if (!present(t))
		return false;
	for (const Carry &c : carries_)
		if (t >= c.start && t < c.end)
			return false;
	return true;
}

} // namespace ihf
