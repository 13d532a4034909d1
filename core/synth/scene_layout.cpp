// SPDX-License-Identifier: MIT
#include "core/synth/scene_layout.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/geometry/rotation.h"
#include "core/synth/primitive_mesh.h"

namespace ihf {

namespace {

Eigen::Matrix3d yawMatrix(double yaw)
{
	return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

} // namespace

SceneObject placeOnTable(const PlaceableModel &model, int restIndex, double yaw,
			 const Eigen::Vector2d &xy, SceneRole role)
{
	const RestingPose &rest = model.restingPoses[restIndex];
	const Eigen::Matrix3d Rz = yawMatrix(yaw);
	// Footprint centre and lowest point of the rested model.
	const Eigen::Vector3d base(0.5 * (rest.min.x() + rest.max.x()),
				   0.5 * (rest.min.y() + rest.max.y()), rest.min.z());
	SceneObject obj;
	obj.mesh = model.mesh;
	obj.role = role;
	obj.objId = model.objId;
	obj.modelToWorld.R = Rz * rest.R;
	obj.modelToWorld.t = Eigen::Vector3d(xy.x(), xy.y(), 0.0) - Rz * base;
	obj.footprint.centre = xy;
	obj.footprint.halfSize = 0.5 * (rest.max - rest.min).head<2>();
	obj.footprint.yaw = yaw;
	obj.height = rest.max.z() - rest.min.z();
	return obj;
}

void moveOnTable(SceneObject &obj, const Eigen::Vector2d &xy)
{
	const Eigen::Vector2d delta = xy - obj.footprint.centre;
	obj.modelToWorld.t.head<2>() += delta;
	obj.footprint.centre = xy;
}

SynthView lookAtTarget(const Eigen::Vector3d &target, double distance, double elevation,
		       double azimuth, double roll, const Eigen::Vector2d &aim,
		       const CameraIntrinsics &K)
{
	SynthView v;
	v.distance = distance;
	v.elevation = elevation;
	v.azimuth = azimuth;
	v.roll = roll;
	v.aim = aim;
	v.centre = target + distance * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
						       std::cos(elevation) * std::sin(azimuth),
						       std::sin(elevation));
	// Look-at frame: z forward, x right (horizontal), y down the image.
	const Eigen::Vector3d z = (target - v.centre).normalized();
	const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
	const Eigen::Vector3d y = z.cross(x);
	Eigen::Matrix3d R;
	R.row(0) = x.transpose();
	R.row(1) = y.transpose();
	R.row(2) = z.transpose();
	// Roll about the optical axis keeps the target on the axis; the aim turn
	// then moves it to the chosen pixel.
	R = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
	const Eigen::Vector3d ray =
		Eigen::Vector3d((aim.x() - K.cx) / K.fx, (aim.y() - K.cy) / K.fy, 1.0).normalized();
	R = rotationBetween(Eigen::Vector3d::UnitZ(), ray) * R;
	v.worldToCamera.R = R;
	v.worldToCamera.t = -R * v.centre;
	return v;
}

PlaceableModel randomPrimitive(SynthRandom &rng, double scale)
{
	const double u = rng.uniform01();
	const double s = scale;
	// Sizes are drawn one statement each, last dimension first: the order
	// of a call's arguments is up to the compiler, and a seed must give the
	// same scene whoever built ihf.
	if (u < 0.3) {
		const double d = rng.logUniform(20 * s, 260 * s), h = rng.logUniform(30 * s, 220 * s);
		return primitiveModel(makeBox(rng.logUniform(30 * s, 220 * s), h, d));
	}
	if (u < 0.42) { // books, boxes lying flat, a tray
		const double d = rng.logUniform(5 * s, 45 * s), h = rng.logUniform(80 * s, 250 * s);
		return primitiveModel(makeBox(rng.logUniform(100 * s, 320 * s), h, d));
	}
	if (u < 0.7) {
		const double length = rng.logUniform(30 * s, 250 * s);
		return primitiveModel(makeCylinder(rng.logUniform(15 * s, 70 * s), length));
	}
	if (u < 0.85) {
		const double length = rng.logUniform(60 * s, 250 * s);
		return primitiveModel(makeLyingCylinder(rng.logUniform(15 * s, 50 * s), length));
	}
	return primitiveModel(makeSphere(rng.logUniform(15 * s, 70 * s)));
}

SceneLayout LayoutSampler::sampleBase(int targetId, SynthRandom &rng, double elevationCapDeg) const
{
	const PlaceableModel &model = library_.model(targetId);
	SceneLayout layout;
	const int rest = rng.chance(params_.uprightProbability) ? uprightRestingPose(model)
							       : sampleRestingPose(model, rng);
	const double yaw = rng.uniform(0, 2 * std::numbers::pi);
	layout.objects.push_back(placeOnTable(model, rest, yaw, {0, 0}, SceneRole::kTarget));
	if (rng.chance(params_.targetDropoutProbability))
		layout.objects[0].dropout = rng.uniform(0.03, params_.targetDropoutMax);

	const double distance = rng.uniform(params_.distanceMin, params_.distanceMax);
	const double elevMax = std::max(params_.elevationMinDeg, std::min(params_.elevationMaxDeg, elevationCapDeg));
	const double elevation = radians(rng.uniform(params_.elevationMinDeg, elevMax));
	const double azimuth = rng.uniform(0, 2 * std::numbers::pi);
	const double roll = radians(std::clamp(rng.normal() * params_.rollSigmaDeg,
					       -params_.rollMaxDeg, params_.rollMaxDeg));
	// Anywhere in the image where the object fits whole (the occlusion
	// control may push it over the border on purpose).
	// Where in the image: around the centre as a person framing the object
	// would hold the camera, but not always in the middle; the whole object
	// stays inside (the occlusion control may push it over the border).
	const double r = 0.5 * model.diameter * K_.fx / distance;
	const double hw = std::clamp(0.5 * K_.width - 0.8 * r - 10, 0.0, 0.3 * K_.width);
	const double hh = std::clamp(0.5 * K_.height - 0.8 * r - 10, 0.0, 0.3 * K_.height);
	const double aimY = 0.5 * K_.height + rng.uniform(-hh, hh); // y first, as the box sizes
	const Eigen::Vector2d aim(0.5 * K_.width + rng.uniform(-hw, hw), aimY);
	layout.view = lookAtTarget(layout.objects[0].modelToWorld.t, distance, elevation, azimuth,
				   roll, aim, K_);
	return layout;
}

void LayoutSampler::reaim(SceneLayout &layout, const Eigen::Vector2d &aim) const
{
	const SynthView &v = layout.view;
	layout.view = lookAtTarget(layout.objects[0].modelToWorld.t, v.distance, v.elevation,
				   v.azimuth, v.roll, aim, K_);
}

bool LayoutSampler::fits(const SceneLayout &layout, const SceneObject &obj, int skip) const
{
	for (size_t i = 0; i < layout.objects.size(); ++i) {
		const SceneObject &o = layout.objects[i];
		if (static_cast<int>(i) == skip || o.role == SceneRole::kRoom)
			continue;
		if (footprintsOverlap(obj.footprint, o.footprint, 0.5))
			return false;
	}
	// Keep clear of the camera (the Kinect sees nothing nearer than ~0.5 m
	// anyway, and a box in front of the lens is no test scene).
	return cameraClearance(obj, layout.view.centre) >= params_.minCameraClearance;
}

double cameraClearance(const SceneObject &obj, const Eigen::Vector3d &cameraCentre)
{
	const Footprint &f = obj.footprint;
	const Eigen::Vector2d d = cameraCentre.head<2>() - f.centre;
	const double u = std::max(std::abs(d.dot(f.axisX())) - f.halfSize.x(), 0.0);
	const double v = std::max(std::abs(d.dot(f.axisY())) - f.halfSize.y(), 0.0);
	const double z = cameraCentre.z();
	const double w = z > obj.height ? z - obj.height : (z < 0 ? -z : 0.0);
	return std::sqrt(u * u + v * v + w * w);
}

double LayoutSampler::clearDistance(const SceneLayout &layout, SceneObject obj,
				    const Eigen::Vector2d &dir, const Eigen::Vector2d &lateral,
				    double gap) const
{
	const Footprint &target = layout.objects[0].footprint;
	const double far = target.radius() + obj.footprint.radius() + gap + 1.0;
	auto overlaps = [&](double d) {
		moveOnTable(obj, target.centre + d * dir + lateral);
		return footprintsOverlap(obj.footprint, target, gap);
	};
	// The overlapping distances form one interval (convex shapes along a
	// line): step in from the far side to its upper end, then bisect.
	double hi = far, lo = far;
	const double step = 2.0;
	while (lo > 0 && !overlaps(lo)) {
		hi = lo;
		lo -= step;
	}
	if (lo <= 0 && !overlaps(0.0))
		return 0.0;
	lo = std::max(lo, 0.0);
	for (int i = 0; i < 20; ++i) {
		const double mid = 0.5 * (lo + hi);
		if (overlaps(mid))
			lo = mid;
		else
			hi = mid;
	}
	return hi;
}

void LayoutSampler::addClutter(SceneLayout &layout, int targetId, SynthRandom &rng) const
{
	addClutter(layout, std::vector<int>{targetId}, rng);
}

void LayoutSampler::addClutter(SceneLayout &layout, const std::vector<int> &excludedIds,
			       SynthRandom &rng) const
{
	std::vector<int> others;
	for (int id : library_.ids())
		if (std::find(excludedIds.begin(), excludedIds.end(), id) == excludedIds.end())
			others.push_back(id);

	const int count = rng.uniformInt(params_.clutterMin, params_.clutterMax);
	for (int k = 0; k < count; ++k) {
		PlaceableModel model;
		if (!others.empty() && rng.chance(params_.meshClutterShare))
			model = library_.model(others[rng.below(others.size())]);
		else
			model = randomPrimitive(rng);
		const int rest = model.objId > 0 && rng.chance(params_.uprightProbability)
					 ? uprightRestingPose(model)
					 : sampleRestingPose(model, rng);
		SceneObject obj = placeOnTable(model, rest, rng.uniform(0, 2 * std::numbers::pi), {0, 0},
					       SceneRole::kClutter);
		obj.dropout = rng.chance(params_.darkProbability) ? rng.uniform(0.6, 1.0) : 0.0;
		const bool touching = rng.chance(params_.touchProbability);
		for (int attempt = 0; attempt < 15; ++attempt) {
			const double a = rng.uniform(0, 2 * std::numbers::pi);
			const Eigen::Vector2d dir(std::cos(a), std::sin(a));
			double d;
			if (touching) {
				d = clearDistance(layout, obj, dir, {0, 0}, rng.uniform(1.0, 4.0));
			} else {
				const double near = clearDistance(layout, obj, dir, {0, 0}, 5.0);
				d = rng.uniform(near, std::max(near, params_.clutterRadius +
									 obj.footprint.radius()));
			}
			moveOnTable(obj, layout.objects[0].footprint.centre + d * dir);
			if (fits(layout, obj)) {
				layout.objects.push_back(obj);
				break;
			}
		}
	}

	// More items further out over the table (a cluttered desk), and large
	// boxes behind the target: shelves, cartons, a monitor's foot.
	const int background = rng.uniformInt(params_.backgroundMin, params_.backgroundMax);
	const Eigen::Vector2d away = layout.objects[0].footprint.centre - layout.view.centre.head<2>();
	const double awayAngle = std::atan2(away.y(), away.x());
	for (int k = 0; k < background; ++k) {
		const double kind = rng.uniform01();
		PlaceableModel model;
		bool big = false;
		if (kind < 0.25 && !others.empty()) {
			model = library_.model(others[rng.below(others.size())]);
		} else if (kind < 0.75) {
			model = randomPrimitive(rng);
		} else {
			const double d = rng.logUniform(80, 350), h = rng.logUniform(150, 450);
			model = primitiveModel(makeBox(rng.logUniform(150, 450), h, d));
			big = true;
		}
		const int rest = model.objId > 0 && rng.chance(params_.uprightProbability)
					 ? uprightRestingPose(model)
					 : sampleRestingPose(model, rng);
		SceneObject obj = placeOnTable(model, rest, rng.uniform(0, 2 * std::numbers::pi), {0, 0},
					       SceneRole::kBackground);
		obj.dropout = rng.chance(params_.darkProbability) ? rng.uniform(0.6, 1.0) : 0.0;
		const double r0 = layout.objects[0].footprint.radius() + obj.footprint.radius();
		for (int attempt = 0; attempt < 10; ++attempt) {
			// Big boxes stand behind the target (within +-70 degrees).
			const double a = big ? awayAngle + rng.uniform(-1.2, 1.2) : rng.uniform(0, 2 * std::numbers::pi);
			const double d = rng.uniform(r0 + 100, r0 + 700);
			moveOnTable(obj, layout.objects[0].footprint.centre +
						 d * Eigen::Vector2d(std::cos(a), std::sin(a)));
			if (fits(layout, obj)) {
				layout.objects.push_back(obj);
				break;
			}
		}
	}
}

void LayoutSampler::addRoom(SceneLayout &layout, SynthRandom &rng) const
{
	const Eigen::Vector2d targetXy = layout.objects[0].footprint.centre;
	Eigen::Vector2d toCam = layout.view.centre.head<2>() - targetXy;
	const double horiz = toCam.norm();
	toCam = horiz > 1e-9 ? Eigen::Vector2d(toCam / horiz) : Eigen::Vector2d(1, 0);

	// The table roughly faces the camera (someone standing at it, or a
	// tripod at its edge): it reaches from part of the way to the camera to
	// some way behind the target, and sideways.
	Footprint table;
	table.yaw = std::atan2(toCam.y(), toCam.x()) + rng.uniform(-0.45, 0.45);
	const double nearEdge = std::max(350.0, rng.uniform(0.8, 1.3) * horiz);
	const double farEdge = rng.uniform(250, 900);
	const double side = rng.uniform(450, 900);
	const double shift = rng.uniform(-0.5, 0.5) * side;
	Eigen::Vector2d lo(-farEdge, -side + shift), hi(nearEdge, side + shift);
	table.centre = targetXy;

	// Grow the table so that everything placed stands on it.
	for (const SceneObject &o : layout.objects) {
		if (o.role == SceneRole::kRoom)
			continue;
		for (const auto &c : o.footprint.corners()) {
			const Eigen::Vector2d d = c - table.centre;
			const Eigen::Vector2d p(d.dot(table.axisX()), d.dot(table.axisY()));
			lo = lo.cwiseMin(p - Eigen::Vector2d::Constant(40));
			hi = hi.cwiseMax(p + Eigen::Vector2d::Constant(40));
		}
	}
	const Eigen::Vector2d mid = 0.5 * (lo + hi);
	table.centre += mid.x() * table.axisX() + mid.y() * table.axisY();
	table.halfSize = 0.5 * (hi - lo);
	layout.table = table;
	layout.tableHeight = rng.uniform(700, 780);

	// Slab: the top sits 0.5 mm under the objects' contact plane so the
	// contact pixels never tie in the z-buffer.
	const double thickness = rng.uniform(18, 40);
	SceneObject slab;
	slab.role = SceneRole::kRoom;
	slab.mesh = std::make_shared<const Mesh>(
		makeBox(2 * table.halfSize.x(), 2 * table.halfSize.y(), thickness));
	slab.modelToWorld.R = yawMatrix(table.yaw);
	slab.modelToWorld.t = {table.centre.x(), table.centre.y(), -0.5 - thickness};
	layout.objects.push_back(slab);

	// The room: a box around the table, seen from inside (floor, ceiling,
	// four walls). The wall behind the table is right at its far edge when
	// the table stands against it, else further off, often beyond the
	// sensor's 4 m.
	layout.wall = rng.chance(params_.wallProbability);
	const double behind = layout.wall ? rng.uniform(0, 150) : rng.uniform(300, 1800);
	const double roomLo = table.halfSize.x() + behind; // along -x of the table
	const double roomHi = table.halfSize.x() + rng.uniform(600, 2500);
	const double roomSide = table.halfSize.y() + rng.uniform(500, 2500);
	const double roomHeight = rng.uniform(2400, 3000);
	SceneObject room;
	room.role = SceneRole::kRoom;
	room.mesh = std::make_shared<const Mesh>(makeBox(roomLo + roomHi, 2 * roomSide, roomHeight));
	room.modelToWorld.R = yawMatrix(table.yaw);
	const Eigen::Vector2d roomCentre = table.centre + 0.5 * (roomHi - roomLo) * table.axisX() +
					   rng.uniform(-0.3, 0.3) * (roomSide - table.halfSize.y()) *
						   table.axisY();
	room.modelToWorld.t = {roomCentre.x(), roomCentre.y(), -layout.tableHeight};
	layout.objects.push_back(room);
}

} // namespace ihf
