// SPDX-License-Identifier: MIT
#include "core/synth/sequence_scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace ihf {

namespace {

constexpr uint64_t kSequenceTag = 0x73657175656e6365ull; // "sequence"
constexpr int kMaxAttempts = 12;

// A target with the resting pose it stands in (a move keeps it).
struct Placed {
	int objId = 0;
	int rest = 0;
};

Eigen::Vector2d unit(double a) { return {std::cos(a), std::sin(a)}; }

bool overlapsAny(const std::vector<SceneObject> &objects, const SceneObject &obj, int skip,
		 double gap)
{
	for (size_t i = 0; i < objects.size(); ++i) {
		if (static_cast<int>(i) == skip || objects[i].role == SceneRole::kRoom)
			continue;
		if (footprintsOverlap(obj.footprint, objects[i].footprint, gap))
			return true;
	}
	return false;
}

// Whether the object's origin is out of the image (by its radius) or
// behind the camera.
bool outOfView(const Pose &worldToCamera, const Eigen::Vector3d &origin, double radius,
	       const CameraIntrinsics &K)
{
	const Eigen::Vector3d q = worldToCamera.apply(origin);
	if (q.z() <= radius)
		return true;
	const Eigen::Vector2d uv = K.project(q);
	const double r = radius * K.fx / q.z();
	return uv.x() < -r || uv.y() < -r || uv.x() > K.width + r || uv.y() > K.height + r;
}

class Planner
{
public:
	Planner(const ModelLibrary &library, const CameraIntrinsics &K, const SequenceParams &params,
		const std::vector<int> &objects, int sequenceId)
		: library_(library), K_(K), p_(params), objects_(objects), sequenceId_(sequenceId),
		  sampler_(library, K, params.synth.layout)
	{
		duration_ = p_.frames / p_.fps;
	}

	Expected<SequenceScene> attempt(uint64_t key, int index);

private:
	SceneObject placeTarget(int objId, int rest, double yaw, const Eigen::Vector2d &xy) const
	{
		return placeOnTable(library_.model(objId), rest, yaw, xy, SceneRole::kTarget);
	}
	double clearance(const SceneObject &obj, int fromFrame, int toFrame) const
	{
		double c = 1e300;
		for (int f = std::max(fromFrame, 0); f < std::min(toFrame, p_.frames); ++f)
			c = std::min(c, cameraClearance(obj, cameras_[static_cast<size_t>(f)]));
		return c;
	}
	// Height to carry obj at between two footprint centres: above whatever
	// stands along the way.
	double liftHeight(const SceneObject &obj, int self, const Eigen::Vector2d &a,
			  const Eigen::Vector2d &b, const std::vector<SceneObject> &objects) const
	{
		double lift = 60;
		SceneObject moving = obj;
		for (int i = 0; i <= 20; ++i) {
			moveOnTable(moving, a + (b - a) * (i / 20.0));
			for (size_t k = 0; k < objects.size(); ++k) {
				const SceneObject &o = objects[k];
				if (static_cast<int>(k) == self || o.role == SceneRole::kRoom)
					continue;
				if (footprintsOverlap(moving.footprint, o.footprint, 10))
					lift = std::max(lift, o.height + 25);
			}
		}
		return lift;
	}
	int frameAt(double t) const { return std::clamp(static_cast<int>(std::floor(t * p_.fps)), 0, p_.frames - 1); }
	// Carry between a resting place and a point off the scene, where the
	// object is out of view at the scene end of the carry.
	bool offScene(const SceneObject &obj, int self, double start, double end, bool away,
		      SynthRandom &rng, Carry &carry, const std::vector<SceneObject> &objects) const;

	const ModelLibrary &library_;
	CameraIntrinsics K_;
	const SequenceParams &p_;
	const std::vector<int> &objects_;
	int sequenceId_;
	LayoutSampler sampler_;
	double duration_ = 0;
	std::vector<Eigen::Vector3d> cameras_; // camera centre per frame
	std::vector<Pose> views_;              // world to camera per frame
	double baseAzimuth_ = 0;
};

bool Planner::offScene(const SceneObject &obj, int self, double start, double end, bool away,
		       SynthRandom &rng, Carry &carry, const std::vector<SceneObject> &objects) const
{
	const double radius = 0.5 * obj.footprint.radius() + 0.5 * obj.height;
	const Eigen::Vector3d rest = obj.modelToWorld.t;
	for (int k = 0; k < 8; ++k) {
		// Sideways from the camera's side of the table, out of the picture.
		// One draw a statement: the order of an expression's operands is
		// the compiler's, and a seed must give one sequence.
		const double side = rng.chance(0.5) ? 0.5 : -0.5;
		const double a = baseAzimuth_ + side * std::numbers::pi + rng.uniform(-0.5, 0.5);
		const double reach = 700 + 350 * k;
		const Eigen::Vector2d far = obj.footprint.centre + reach * unit(a);
		const double lift = liftHeight(obj, self, obj.footprint.centre, far, objects);
		const Eigen::Vector3d off =
			rest + Eigen::Vector3d(reach * std::cos(a), reach * std::sin(a), std::max(lift + 100, 300.0));
		Carry c;
		c.kind = away ? CarryKind::kTakeAway : CarryKind::kPutDown;
		c.start = start;
		c.end = end;
		c.from = obj.modelToWorld;
		c.to = obj.modelToWorld;
		(away ? c.to : c.from).t = off;
		(away ? c.liftFrom : c.liftTo) = lift;
		// Out of view where it appears or vanishes, and never in front of
		// the lens on the way.
		const int edge = away ? frameAt(end) : frameAt(start);
		bool ok = true;
		for (int f = std::max(edge - 1, 0); f <= std::min(edge + 1, p_.frames - 1) && ok; ++f)
			ok = outOfView(views_[static_cast<size_t>(f)], off, radius, K_);
		for (int f = frameAt(start); f <= frameAt(end) && ok; ++f) {
			const Pose at = carryPose(c, std::clamp((f / p_.fps - start) / (end - start), 0.0, 1.0));
			ok = (at.t - cameras_[static_cast<size_t>(f)]).norm() > 350.0;
		}
		if (ok) {
			carry = c;
			return true;
		}
	}
	return false;
}

Expected<SequenceScene> Planner::attempt(uint64_t key, int index)
{
	SynthRandom rng(mixSeed(key, static_cast<uint64_t>(index)));
	auto fail = [&](const std::string &why) {
		return makeError(Errc::kOutOfRange, "synth: sequence " + std::to_string(sequenceId_) + ": " + why);
	};
	const LayoutParams &lp = p_.synth.layout;
	SequenceScene scene;
	scene.sequenceId = sequenceId_;
	scene.key = key;

	// Which targets, and whether one is taken away or put down.
	const int n = rng.uniformInt(p_.perFrameMin, p_.perFrameMax);
	std::vector<int> order = objects_;
	for (size_t i = order.size(); i > 1; --i)
		std::swap(order[i - 1], order[rng.below(i)]);
	enum class Change { kNone, kTakeAway, kPutDown } change = Change::kNone;
	if (rng.chance(p_.changeProbability)) {
		std::vector<Change> feasible;
		if (n - 1 >= p_.perFrameMin)
			feasible.push_back(Change::kTakeAway);
		if (n + 1 <= p_.perFrameMax && static_cast<int>(order.size()) > n)
			feasible.push_back(Change::kPutDown);
		if (!feasible.empty())
			change = feasible[rng.below(feasible.size())];
	}
	const int slots = n + (change == Change::kPutDown ? 1 : 0);

	// The side of the table the camera works from.
	baseAzimuth_ = rng.uniform(0, 2 * std::numbers::pi);

	// The targets: the first at the origin, the others close around it,
	// mostly in front of or behind one another as seen from the camera's
	// side, so that they hide each other as the view swings.
	SceneLayout &layout = scene.layout;
	std::vector<Placed> placed;
	for (int i = 0; i < slots; ++i) {
		const PlaceableModel &model = library_.model(order[static_cast<size_t>(i)]);
		const int rest = rng.chance(lp.uprightProbability) ? uprightRestingPose(model)
								   : sampleRestingPose(model, rng);
		SceneObject obj = placeTarget(model.objId, rest, rng.uniform(0, 2 * std::numbers::pi), {0, 0});
		if (rng.chance(lp.targetDropoutProbability))
			obj.dropout = rng.uniform(0.03, lp.targetDropoutMax);
		bool ok = i == 0;
		for (int t = 0; t < 40 && !ok; ++t) {
			// Beside a target already placed, a small gap between them.
			SceneLayout anchor;
			anchor.objects.push_back(layout.objects[rng.below(layout.objects.size())]);
			const double end = rng.chance(0.5) ? 0.0 : std::numbers::pi; // one draw a statement
			const double along = baseAzimuth_ + end + rng.uniform(-0.7, 0.7);
			// In line first; anywhere around when the line is full.
			const bool inLine = t < 20 && rng.chance(p_.inLineProbability);
			const Eigen::Vector2d dir = unit(inLine ? along : rng.uniform(0, 2 * std::numbers::pi));
			const double clear = sampler_.clearDistance(anchor, obj, dir, {0, 0},
								     rng.uniform(2.0, p_.targetGapMax));
			const double d = clear + (t / 40.0) * 100.0 * rng.uniform01();
			moveOnTable(obj, anchor.objects[0].footprint.centre + d * dir);
			ok = obj.footprint.centre.norm() <= p_.groupRadius && !overlapsAny(layout.objects, obj, -1, 2.0);
		}
		if (!ok)
			return fail("no room for " + std::to_string(slots) + " targets within " +
				    std::to_string(static_cast<int>(p_.groupRadius)) + " mm of the first");
		layout.objects.push_back(obj);
		placed.push_back({model.objId, rest});
	}
	Eigen::Vector2d mean = Eigen::Vector2d::Zero();
	for (int i = 0; i < slots; ++i)
		mean += layout.objects[static_cast<size_t>(i)].footprint.centre;
	mean /= slots;
	scene.centre = Eigen::Vector3d(mean.x(), mean.y(), 40.0);

	// The camera's path, clear of every target.
	CameraPathParams pp = p_.path;
	pp.style = p_.motion == CameraMotion::kMixed
			   ? (rng.chance(0.5) ? CameraMotion::kHandheld : CameraMotion::kRobot)
			   : p_.motion;
	pp.durationS = duration_;
	scene.path = CameraPath::sample(pp, K_, scene.centre, baseAzimuth_, rng);
	cameras_.clear();
	views_.clear();
	for (int f = 0; f < p_.frames; ++f) {
		views_.push_back(scene.path.worldToCamera(f / p_.fps));
		cameras_.push_back(views_.back().inverse().t);
	}
	for (int i = 0; i < slots; ++i)
		if (clearance(layout.objects[static_cast<size_t>(i)], 0, p_.frames) < lp.minCameraClearance)
			return fail("the camera's path comes too near a target (try a larger --distance)");
	layout.view.worldToCamera = views_[0];
	layout.view.centre = cameras_[0];

	// Clutter (never a model of --objects), and nothing the camera would
	// pass through.
	sampler_.addClutter(layout, objects_, rng);
	for (size_t i = layout.objects.size(); i-- > static_cast<size_t>(slots);)
		if (clearance(layout.objects[i], 0, p_.frames) < lp.minCameraClearance)
			layout.objects.erase(layout.objects.begin() + static_cast<std::ptrdiff_t>(i));

	// The events, each in its own window of the sequence's middle.
	struct Event {
		CarryKind kind;
		int slot;
	};
	std::vector<Event> events;
	std::vector<int> initial(static_cast<size_t>(n));
	for (int i = 0; i < n; ++i)
		initial[static_cast<size_t>(i)] = i;
	const int removed = change == Change::kTakeAway ? static_cast<int>(rng.below(n)) : -1;
	std::vector<int> movable;
	for (int i : initial)
		if (i != removed)
			movable.push_back(i);
	events.push_back({CarryKind::kMove, movable[rng.below(movable.size())]});
	if (change == Change::kTakeAway)
		events.push_back({CarryKind::kTakeAway, removed});
	if (change == Change::kPutDown)
		events.push_back({CarryKind::kPutDown, slots - 1});
	if (events.size() == 2 && rng.chance(0.5))
		std::swap(events[0], events[1]);

	for (int i = 0; i < slots; ++i)
		scene.targets.push_back({placed[static_cast<size_t>(i)].objId,
					 ObjectSchedule(layout.objects[static_cast<size_t>(i)].modelToWorld), {}});
	std::vector<SceneObject> reserved = layout.objects; // with the new places
	const double window = 0.8 * duration_ / static_cast<double>(events.size());
	for (size_t e = 0; e < events.size(); ++e) {
		const Event &ev = events[e];
		const double length = std::min(rng.uniform(p_.carrySecondsMin, p_.carrySecondsMax), 0.8 * window);
		const double start = 0.1 * duration_ + e * window + rng.uniform(0, window - length);
		const double end = start + length;
		const SceneObject &obj = layout.objects[static_cast<size_t>(ev.slot)];
		TargetSlot &slot = scene.targets[static_cast<size_t>(ev.slot)];
		Carry carry;
		bool ok = false;
		if (ev.kind == CarryKind::kMove) {
			const Placed &pl = placed[static_cast<size_t>(ev.slot)];
			for (int t = 0; t < 80 && !ok; ++t) {
				const Eigen::Vector2d dir = unit(rng.uniform(0, 2 * std::numbers::pi)); // then the radius
				const Eigen::Vector2d xy = mean + p_.groupRadius * std::sqrt(rng.uniform01()) * dir;
				SceneObject dest = placeTarget(pl.objId, pl.rest, rng.uniform(0, 2 * std::numbers::pi), xy);
				if ((xy - obj.footprint.centre).norm() < 80.0 ||
				    overlapsAny(reserved, dest, ev.slot, 2.0) ||
				    clearance(dest, frameAt(start), p_.frames) < lp.minCameraClearance)
					continue;
				carry.kind = CarryKind::kMove;
				carry.start = start;
				carry.end = end;
				carry.from = obj.modelToWorld;
				carry.to = dest.modelToWorld;
				carry.liftFrom = carry.liftTo =
					liftHeight(obj, ev.slot, obj.footprint.centre, xy, reserved);
				dest.role = SceneRole::kTarget;
				reserved.push_back(dest);
				ok = true;
			}
		} else {
			ok = offScene(obj, ev.slot, start, end, ev.kind == CarryKind::kTakeAway, rng, carry,
				      reserved);
			if (ok && ev.kind == CarryKind::kPutDown)
				slot.schedule = ObjectSchedule(carry.from);
		}
		if (!ok)
			return fail("no place for an object's move");
		slot.schedule.add(carry);
	}

	// The table holds every place a target takes, the room around it.
	SceneLayout withPlaces = layout;
	withPlaces.objects = reserved;
	sampler_.addRoom(withPlaces, rng);
	layout.table = withPlaces.table;
	layout.tableHeight = withPlaces.tableHeight;
	layout.wall = withPlaces.wall;
	for (const SceneObject &o : withPlaces.objects)
		if (o.role == SceneRole::kRoom)
			layout.objects.push_back(o);

	for (TargetSlot &slot : scene.targets)
		slot.misses = detectorMisses(p_.frames, p_.detector, rng);
	return scene;
}

} // namespace

Expected<SequenceScene> planSequenceScene(const ModelLibrary &library, const CameraIntrinsics &K,
					  const SequenceParams &params,
					  const std::vector<int> &objects, int sequenceId)
{
	const uint64_t key = mixSeed(mixSeed(params.synth.seed, kSequenceTag),
				     static_cast<uint64_t>(sequenceId));
	Planner planner(library, K, params, objects, sequenceId);
	Error last = makeError(Errc::kOutOfRange, "");
	for (int a = 0; a < kMaxAttempts; ++a) {
		auto scene = planner.attempt(key, a);
		if (scene) {
			scene->attempts = a + 1;
			return scene;
		}
		last = scene.error();
	}
	return makeError(Errc::kOutOfRange,
			 last.message + " (after " + std::to_string(kMaxAttempts) + " attempts)");
}

} // namespace ihf
