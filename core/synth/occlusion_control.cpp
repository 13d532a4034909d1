// SPDX-License-Identifier: MIT
#include "core/synth/occlusion_control.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/synth/primitive_mesh.h"

namespace ihf {

OcclusionMeter::OcclusionMeter(SceneRenderer &renderer, const ObjectSilhouette &target,
			       const Pose &worldToCamera)
	: renderer_(renderer), target_(target), worldToCamera_(worldToCamera)
{
	const CameraIntrinsics &K = renderer_.intrinsics();
	cx0_ = std::max(target.x0, 0);
	cy0_ = std::max(target.y0, 0);
	cw_ = std::max(0, std::min(target.x0 + target.width, K.width) - cx0_);
	ch_ = std::max(0, std::min(target.y0 + target.height, K.height) - cy0_);
	scratch_.assign(static_cast<size_t>(cw_) * ch_, 0.0f);
	for (int y = 0; y < ch_; ++y)
		for (int x = 0; x < cw_; ++x)
			if (target_.at(x + cx0_, y + cy0_) > 0.0f)
				++inImage_;
}

Expected<std::vector<uint8_t>> OcclusionMeter::cover(const SceneObject &obj)
{
	std::vector<uint8_t> mask(static_cast<size_t>(cw_) * ch_, 0);
	if (cw_ == 0 || ch_ == 0)
		return mask;
	std::fill(scratch_.begin(), scratch_.end(), 0.0f);
	ImageView<float> view(scratch_.data(), cw_, ch_);
	Status s = renderer_.renderObject(obj, worldToCamera_, view, {}, 0, RenderWindow{cx0_, cy0_});
	if (!s)
		return s.error();
	for (int y = 0; y < ch_; ++y) {
		for (int x = 0; x < cw_; ++x) {
			const float t = target_.at(x + cx0_, y + cy0_);
			const float o = view.at(x, y);
			if (t > 0.0f && o > 0.0f && o < t)
				mask[static_cast<size_t>(y) * cw_ + x] = 1;
		}
	}
	return mask;
}

double OcclusionMeter::occlusion(const std::vector<std::vector<uint8_t>> &covers) const
{
	if (target_.pxCountAll <= 0)
		return 1.0;
	int visible = 0;
	for (int y = 0; y < ch_; ++y) {
		for (int x = 0; x < cw_; ++x) {
			if (target_.at(x + cx0_, y + cy0_) <= 0.0f)
				continue;
			const size_t i = static_cast<size_t>(y) * cw_ + x;
			bool hidden = false;
			for (const auto &c : covers) {
				if (!c.empty() && c[i]) {
					hidden = true;
					break;
				}
			}
			visible += hidden ? 0 : 1;
		}
	}
	return 1.0 - static_cast<double>(visible) / target_.pxCountAll;
}

double OcclusionMeter::truncation() const
{
	if (target_.pxCountAll <= 0)
		return 1.0;
	return 1.0 - static_cast<double>(inImage_) / target_.pxCountAll;
}

int OcclusionMeter::count(const std::vector<uint8_t> &mask)
{
	return static_cast<int>(std::count(mask.begin(), mask.end(), uint8_t{1}));
}

namespace {

Expected<double> truncationAt(SceneRenderer &renderer, const SceneLayout &layout)
{
	auto sil = renderer.silhouette(layout.objects[0], layout.view.worldToCamera);
	if (!sil)
		return sil.error();
	OcclusionMeter meter(renderer, *sil, layout.view.worldToCamera);
	return meter.truncation();
}

} // namespace

Status OcclusionController::placeTruncation(SceneLayout &layout, const OcclusionGoal &goal,
					    SynthRandom &rng, OcclusionOutcome &out)
{
	const CameraIntrinsics &K = renderer_.intrinsics();
	const Eigen::Vector2d centre(0.5 * K.width, 0.5 * K.height);
	const Eigen::Vector2d aim0 = layout.view.aim;
	double wanted = 0;
	if (goal.goal >= 0.1 && rng.chance(goal.truncationProbability))
		wanted = goal.goal * rng.uniform(0.5, 1.0);

	auto trunc = truncationAt(renderer_, layout);
	if (!trunc)
		return trunc.error();
	if (wanted > 0) {
		// Slide the target towards a random border until the border cuts
		// off the wanted share (grows monotonically along the slide).
		const double a = rng.uniform(0, 2 * std::numbers::pi);
		const Eigen::Vector2d dir(std::cos(a), std::sin(a));
		const double reach = 0.5 * std::hypot(K.width, K.height) +
				     0.5 * sampler_.library().model(layout.objects[0].objId).diameter *
					     K.fx / layout.view.distance;
		double lo = 0, hi = 1;
		for (int i = 0; i < 14; ++i) {
			const double mid = 0.5 * (lo + hi);
			sampler_.reaim(layout, aim0 + mid * reach * dir);
			auto t = truncationAt(renderer_, layout);
			if (!t)
				return t.error();
			if (*t < wanted)
				lo = mid;
			else
				hi = mid;
			if (std::abs(*t - wanted) < 0.25 * goal.tolerance)
				break;
		}
	} else if (*trunc > 0.5 * goal.goal) {
		// Keep most of the budget for occluders: pull the aim inwards.
		double lo = 0, hi = 1;
		for (int i = 0; i < 12; ++i) {
			const double mid = 0.5 * (lo + hi);
			sampler_.reaim(layout, centre + mid * (aim0 - centre));
			auto t = truncationAt(renderer_, layout);
			if (!t)
				return t.error();
			if (*t <= 0.5 * goal.goal)
				lo = mid;
			else
				hi = mid;
		}
		sampler_.reaim(layout, centre + lo * (aim0 - centre));
	}
	trunc = truncationAt(renderer_, layout);
	if (!trunc)
		return trunc.error();
	out.truncation = *trunc;
	return {};
}

Expected<bool> OcclusionController::addOccluder(SceneLayout &layout, OcclusionMeter &meter,
						std::vector<std::vector<uint8_t>> &covers,
						double goal, double tolerance, SynthRandom &rng)
{
	const SceneObject &target = layout.objects[0];
	const Eigen::Vector3d cam = layout.view.centre;
	Eigen::Vector2d toCam = cam.head<2>() - target.footprint.centre;
	const double horiz = std::max(toCam.norm(), 1.0);
	toCam /= horiz;
	const Eigen::Vector2d lateral(-toCam.y(), toCam.x());
	const double side = rng.chance(0.5) ? 1.0 : -1.0;
	const double gap = rng.uniform(2.0, 50.0);

	std::vector<int> others;
	for (int id : sampler_.library().ids())
		if (id != target.objId)
			others.push_back(id);
	const bool useMesh = !others.empty() && rng.chance(0.4);
	const double kind = rng.uniform01();
	const double aimHeight = target.height * rng.uniform(0.3, 1.0);
	const double widthShare = rng.uniform(0.5, 1.3);
	const double depth = rng.logUniform(30, 150);
	const double yawJitter = rng.uniform(-0.35, 0.35);
	const double heightGain = rng.uniform(0.9, 1.3);
	const bool dark = rng.chance(sampler_.params().darkProbability);
	const double dropout = dark ? rng.uniform(0.6, 1.0) : 0.0;
	const int meshId = others.empty() ? 0 : others[rng.below(others.size())];
	const double meshYaw = rng.uniform(0, 2 * std::numbers::pi);

	// An occluder of a given scale: tall enough that the sight line from
	// the camera to a point aimHeight up the target passes below its top.
	auto make = [&](double scale, bool mesh) {
		if (mesh) {
			const PlaceableModel &m = sampler_.library().model(meshId);
			SceneObject o = placeOnTable(m, sampleRestingPose(m, rng), meshYaw, {0, 0},
						     SceneRole::kOccluder);
			return o;
		}
		const double dist = 0.7 * target.footprint.radius() + 0.5 * depth + gap;
		const double h = std::clamp((aimHeight + dist * (cam.z() - aimHeight) / horiz) *
						    heightGain * scale,
					    25.0, 450.0);
		const double w = std::clamp(widthShare * 2 * target.footprint.radius() * scale, 30.0,
					    350.0);
		const double yaw = std::atan2(toCam.y(), toCam.x()) + yawJitter;
		PlaceableModel m = kind < 0.6 ? primitiveModel(makeBox(depth, w, h))
					      : primitiveModel(makeCylinder(std::clamp(0.5 * w, 15.0, 110.0), h));
		return placeOnTable(m, 0, yaw, {0, 0}, SceneRole::kOccluder);
	};

	SceneObject occ;
	auto occlusionAt = [&](double s) -> Expected<double> {
		const Eigen::Vector2d lat = side * s * lateral;
		const double d = sampler_.clearDistance(layout, occ, toCam, lat, gap);
		moveOnTable(occ, target.footprint.centre + d * toCam + lat);
		auto c = meter.cover(occ);
		if (!c)
			return c.error();
		covers.push_back(std::move(*c));
		const double o = meter.occlusion(covers);
		covers.pop_back();
		return o;
	};

	const double before = meter.occlusion(covers);
	double scale = 1.0;
	bool mesh = useMesh;
	double o0 = 0;
	for (int attempt = 0; attempt < 5; ++attempt) {
		occ = make(scale, mesh);
		auto o = occlusionAt(0.0);
		if (!o)
			return o.error();
		o0 = *o;
		if (o0 >= goal - 0.5 * tolerance)
			break;
		// Too small: a larger primitive (meshes keep their size).
		mesh = false;
		scale *= 1.35;
	}
	double s = 0;
	if (o0 > goal + 0.5 * tolerance) {
		double lo = 0, hi = target.footprint.radius() + occ.footprint.radius() + 40;
		for (int i = 0; i < 18; ++i) {
			const double mid = 0.5 * (lo + hi);
			auto o = occlusionAt(mid);
			if (!o)
				return o.error();
			if (std::abs(*o - goal) < 0.3 * tolerance) {
				lo = hi = mid;
				break;
			}
			if (*o > goal)
				lo = mid;
			else
				hi = mid;
		}
		s = 0.5 * (lo + hi);
	} else if (o0 < before + 0.01) {
		return false; // this occluder cannot help
	}
	auto placed = occlusionAt(s);
	if (!placed)
		return placed.error();
	occ.dropout = dropout;

	// Clear the occluder's spot of clutter, then check the camera clearance.
	for (size_t i = layout.objects.size(); i-- > 1;) {
		const SceneObject &o = layout.objects[i];
		if (o.role == SceneRole::kRoom)
			continue;
		if (footprintsOverlap(occ.footprint, o.footprint, 0.5)) {
			layout.objects.erase(layout.objects.begin() + static_cast<long>(i));
			covers.erase(covers.begin() + static_cast<long>(i));
		}
	}
	if (!sampler_.fits(layout, occ))
		return false;
	auto c = meter.cover(occ);
	if (!c)
		return c.error();
	layout.objects.push_back(occ);
	covers.push_back(std::move(*c));
	return true;
}

Expected<OcclusionOutcome> OcclusionController::apply(SceneLayout &layout,
						       const OcclusionGoal &goal,
						       SynthRandom &rng)
{
	OcclusionOutcome out;
	Status st = placeTruncation(layout, goal, rng, out);
	if (!st)
		return st.error();

	auto sil = renderer_.silhouette(layout.objects[0], layout.view.worldToCamera);
	if (!sil)
		return sil.error();
	OcclusionMeter meter(renderer_, *sil, layout.view.worldToCamera);

	// covers[i] belongs to layout.objects[i]; the target's own stays empty.
	std::vector<std::vector<uint8_t>> covers(layout.objects.size());
	for (size_t i = 1; i < layout.objects.size(); ++i) {
		auto c = meter.cover(layout.objects[i]);
		if (!c)
			return c.error();
		covers[i] = std::move(*c);
	}
	const double lo = std::max(goal.min, goal.goal - goal.tolerance);
	const double hi = std::min(goal.max, goal.goal + goal.tolerance);
	double occ = meter.occlusion(covers);

	// Too much: move the worst-hiding clutter away, or drop it.
	while (occ > hi) {
		size_t worst = 0;
		int worstCount = 0;
		for (size_t i = 1; i < covers.size(); ++i) {
			const int n = OcclusionMeter::count(covers[i]);
			if (n > worstCount) {
				worstCount = n;
				worst = i;
			}
		}
		if (worst == 0)
			break; // nothing left to move: the border alone is too much
		SceneObject obj = layout.objects[worst];
		bool moved = false;
		for (int attempt = 0; attempt < 6 && !moved; ++attempt) {
			const double a = rng.uniform(0, 2 * std::numbers::pi);
			const Eigen::Vector2d dir(std::cos(a), std::sin(a));
			const double near = sampler_.clearDistance(layout, obj, dir, {0, 0}, 5.0);
			const double d = rng.uniform(near, near + sampler_.params().clutterRadius);
			moveOnTable(obj, layout.objects[0].footprint.centre + d * dir);
			if (!sampler_.fits(layout, obj, static_cast<int>(worst)))
				continue;
			auto c = meter.cover(obj);
			if (!c)
				return c.error();
			if (OcclusionMeter::count(*c) == 0) {
				layout.objects[worst] = obj;
				covers[worst] = std::move(*c);
				moved = true;
			}
		}
		if (moved) {
			++out.clutterMoved;
		} else {
			layout.objects.erase(layout.objects.begin() + static_cast<long>(worst));
			covers.erase(covers.begin() + static_cast<long>(worst));
			++out.clutterRemoved;
		}
		occ = meter.occlusion(covers);
	}

	// Too little: stand occluders in front of the target.
	const double aim = std::clamp(goal.goal, lo, hi);
	for (int k = 0; k < 4 && occ < lo; ++k) {
		auto added = addOccluder(layout, meter, covers, aim, goal.tolerance, rng);
		if (!added)
			return added.error();
		out.occluders += *added ? 1 : 0;
		occ = meter.occlusion(covers);
	}
	out.occlusion = occ;
	return out;
}

} // namespace ihf
