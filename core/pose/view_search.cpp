// SPDX-License-Identifier: MIT
#include "core/pose/view_search.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include "core/geometry/rotation.h"
#include "core/pose/depth_agreement.h"
#include "core/pose/median_select.h"

namespace ihf {

Eigen::Matrix3d viewRotation(const ViewTemplates &t, int inplane, int v, int turn)
{
	return lookAtRotation(fibonacciDirection(v, t.viewpoints), 2.0 * M_PI * turn / inplane);
}

namespace {

// Points by coordinate (one array each, so that a loop over them runs on
// vector lanes).
struct ViewPoints {
	std::array<float, kMaxViewPoints> x, y, z;

	Eigen::Vector3f at(int i) const { return {x[i], y[i], z[i]}; }
	void set(int i, const Eigen::Vector3f &p)
	{
		x[i] = p.x();
		y[i] = p.y();
		z[i] = p.z();
	}
};

// Points of one view already rotated by the view's rotation; an in-plane
// turn (c, s) then only mixes x and y.
struct TurnedView {
	const ViewPoints *a;
	int n;
	float c, s;
};

// The extent of projected points, in pixels of the window.
struct PixelExtent {
	float u0 = 0, u1 = 0, w0 = 0, w1 = 0;
};

// The extent of n projections (u, w), four lanes at a time: a loop's own
// min and max over floats would keep the loop that fills u and w off vector
// lanes. A NaN is passed over as std::min passes it over (on NEON, where
// the lanes keep it, the extent is NaN and the box agreement 0: a point at
// the camera's centre).
PixelExtent extentOf(const float *u, const float *w, int n)
{
	using Lanes = Eigen::Array4f;
	Lanes u0 = Lanes::Constant(1e30f), u1 = Lanes::Constant(-1e30f), w0 = u0, w1 = u1;
	int i = 0;
	for (; i + 4 <= n; i += 4) {
		const Lanes a = Lanes::Map(u + i), b = Lanes::Map(w + i);
		u0 = u0.min(a);
		u1 = u1.max(a);
		w0 = w0.min(b);
		w1 = w1.max(b);
	}
	PixelExtent e{u0.minCoeff(), u1.maxCoeff(), w0.minCoeff(), w1.maxCoeff()};
	for (; i < n; ++i) {
		e.u0 = std::min(e.u0, u[i]);
		e.u1 = std::max(e.u1, u[i]);
		e.w0 = std::min(e.w0, w[i]);
		e.w1 = std::max(e.w1, w[i]);
	}
	return e;
}

struct Tally {
	int in = 0, out = 0, occ = 0, outside = 0;
	float fit = 0; // inliers weighted by residual (the score's rule)
	PixelExtent extent; // of the points, for the agreement with the box
};

class SparseScorer
{
public:
	SparseScorer(const ViewSearchConfig &config, ImageView<const float> observed, const CameraIntrinsics &K,
		     BoxAxes box)
		: cfg_(config), obs_(observed), fx_(static_cast<float>(K.fx)), fy_(static_cast<float>(K.fy)),
		  cx_(static_cast<float>(K.cx)), cy_(static_cast<float>(K.cy)), box_(box)
	{
	}

	// Classifies the points at translation t. Two loops: the projection,
	// branch-free so that it runs on vector lanes, then the lookups in
	// point order.
	Tally tally(const TurnedView &v, const Eigen::Vector3f &t) const
	{
		std::array<int, kMaxViewPoints> pixel;
		std::array<float, kMaxViewPoints> depth;
		Tally k;
		k.outside = project(v, t, pixel.data(), depth.data(), &k.extent);
		// Branch-free: whether a point is compared or an inlier is random
		// from point to point, and mispredicted branches cost more than
		// the work each point does anyway.
		const float *const obs = obs_.data;
		for (int i = 0; i < v.n; ++i) {
			const int p = pixel[i];
			const float o = obs[p < 0 ? 0 : p];
			const int valid = (p >= 0) & (o > 0);
			classifyIf(k, o - depth[i], valid);
		}
		return k;
	}

	// What one projection at t gives before any classification.
	struct Gathered {
		int compared = 0; // residuals written to `all`
		int residuals = 0; // of them within the shift range, written to `res`
		int outside = 0;
		PixelExtent extent;
	};

	// The residuals of the points at t the sensor saw, in point order: all
	// into `all` when it is not null, those within the shift range into
	// `res`; the extent only when `extent` is set. Stores instead of
	// branches, as in tally().
	Gathered gather(const TurnedView &v, const Eigen::Vector3f &t, float *res, float *all, bool extent) const
	{
		std::array<int, kMaxViewPoints> pixel;
		std::array<float, kMaxViewPoints> depth;
		std::array<float, kMaxViewPoints> scratch;
		Gathered g;
		g.outside = project(v, t, pixel.data(), depth.data(), extent ? &g.extent : nullptr);
		float *const kept = all ? all : scratch.data();
		const float *const obs = obs_.data;
		const float maxShift = cfg_.maxShiftMm, minShift = minShiftMm();
		for (int i = 0; i < v.n; ++i) {
			const int p = pixel[i];
			const float o = obs[p < 0 ? 0 : p];
			const int valid = (p >= 0) & (o > 0);
			const float e = o - depth[i];
			kept[g.compared] = e;
			g.compared += valid;
			res[g.residuals] = e;
			g.residuals += valid & (e > minShift) & (e < maxShift);
		}
		return g;
	}

	// The smallest residual that moves the model along its ray. Placed by
	// the box's size, the object is where the box says and may be behind
	// what the sensor saw there: only residuals from the inlier band
	// behind move it (one seen in front is an occluder).
	float minShiftMm() const { return cfg_.placeBySize ? -cfg_.inlierMm : -cfg_.maxShiftMm; }

	// Each point's pixel (offset into obs_, -1 when it falls outside the
	// image) and depth at translation t, and the points' extent when
	// extent is not null; returns how many points count as outside: behind
	// the camera, or past a side of the image that the frame did not clip
	// (past a clipped side the point is unseen: the object may go on
	// there, a border box).
	int project(const TurnedView &v, const Eigen::Vector3f &t, int *pixel, float *depth, PixelExtent *extent) const
	{
		// Everything the loop reads into locals: the stores through
		// pixel and depth could otherwise alias them, which keeps the loop
		// off vector lanes.
		const float width = static_cast<float>(obs_.width), height = static_cast<float>(obs_.height);
		const int left = !box_.open.left, right = !box_.open.right, top = !box_.open.top,
			  bottom = !box_.open.bottom;
		const int n = v.n, stride = obs_.stride;
		const float c = v.c, s = v.s, tx = t.x(), ty = t.y(), tz = t.z();
		const float fx = fx_, fy = fy_, cx = cx_, cy = cy_;
		const float *ax = v.a->x.data(), *ay = v.a->y.data(), *az = v.a->z.data();
		// No points: nothing outside, the empty extent (and GCC sees the
		// arrays below written before extentOf() reads them).
		if (n <= 0) {
			if (extent)
				*extent = extentOf(nullptr, nullptr, 0);
			return 0;
		}
		std::array<float, kMaxViewPoints> us, ws;
		float *const pu = us.data(), *const pw = ws.data();
		int outside = 0;
		for (int i = 0; i < n; ++i) {
			const float z = az[i] + tz;
			const float x = c * ax[i] - s * ay[i] + tx;
			const float y = s * ax[i] + c * ay[i] + ty;
			// floor(f) is below 0 or at least the size exactly when f is.
			const float fu = fx * x / z + cx + 0.5f;
			const float fw = fy * y / z + cy + 0.5f;
			pu[i] = fu;
			pw[i] = fw;
			// Bitwise, not short-circuit: no branch in the loop.
			const int front = z > 1.0f;
			const int lo = fu < 0, hi = fu >= width, up = fw < 0, down = fw >= height;
			const int inside = front & (1 - (lo | hi | up | down));
			outside += (1 - front) | (lo & left) | (hi & right) | (up & top) | (down & bottom);
			const int u = static_cast<int>(inside ? fu : 0.0f);
			const int w = static_cast<int>(inside ? fw : 0.0f);
			pixel[i] = inside ? w * stride + u : -1;
			depth[i] = z;
		}
		if (extent)
			*extent = extentOf(pu, pw, n);
		return outside;
	}

	// One residual (observed - model depth) into the tally when `valid`
	// (1) is set, without a branch.
	void classifyIf(Tally &k, float e, int valid) const
	{
		const int in = valid & (std::abs(e) <= cfg_.inlierMm);
		const int out = valid & (1 - in) & (e > 0);
		k.in += in;
		k.out += out;
		k.occ += valid & (1 - in) & (1 - out);
		// The fit of every residual, kept by a mask: a select here becomes a
		// branch around the division, mispredicted as often as not. Adding
		// the masked +0 leaves the sum as it is, the same sum as a branch.
		const float fit = inlierFit(e, cfg_.inlierMm, cfg_.residualWeight);
		k.fit += std::bit_cast<float>(std::bit_cast<uint32_t>(fit) & (0u - static_cast<uint32_t>(in)));
	}

	// The points' projected extent at t, in pixels from the optical axis;
	// `behind` when a point is not in front of the camera.
	struct Extent {
		float u0 = 1e30f, u1 = -1e30f, w0 = 1e30f, w1 = -1e30f;
		bool behind = false;
	};
	Extent extent(const TurnedView &v, const Eigen::Vector3f &t) const
	{
		// The projections on vector lanes, then their extent.
		std::array<float, kMaxViewPoints> us, ws;
		const float *ax = v.a->x.data(), *ay = v.a->y.data(), *az = v.a->z.data();
		int behind = 0;
		for (int i = 0; i < v.n; ++i) {
			const float z = az[i] + t.z();
			behind |= !(z > 1.0f);
			us[i] = fx_ * (v.c * ax[i] - v.s * ay[i] + t.x()) / z;
			ws[i] = fy_ * (v.s * ax[i] + v.c * ay[i] + t.y()) / z;
		}
		Extent e;
		e.behind = behind;
		if (behind)
			return e;
		const PixelExtent p = extentOf(us.data(), ws.data(), v.n);
		e.u0 = p.u0;
		e.u1 = p.u1;
		e.w0 = p.w0;
		e.w1 = p.w1;
		return e;
	}

	// Translation at t's depth that puts the centre of the extent (at t)
	// on the optical axis; on an axis the frame clipped on one side, the
	// extent's edge on the box's other side (axes with neither keep t's).
	// With inset > 0 an extent placed against a side of the box (an axis
	// clipped on the other) goes that share of its size further inside.
	// (sx, sy): the placement then moved by that share of the extent along
	// x and y. One extent serves every placement of a rotation.
	Eigen::Vector3f centred(const Extent &e, const Eigen::Vector3f &t, float inset = 0.0f, float sx = 0.0f,
				float sy = 0.0f) const
	{
		if (e.behind)
			return t;
		// The box centre is on the optical axis (virtual_crop.h): the
		// extent's offset from it, as a lateral move at t's depth. The
		// window's sides, in the same units, are at -c - 0.5 and size - c - 0.5.
		auto offset = [inset](float lo, float hi, float c, int size, bool trusted, bool openLo, bool openHi) {
			if (trusted)
				return 0.5f * (lo + hi);
			if (openLo && !openHi)
				return hi - (static_cast<float>(size) - c - 0.5f) + inset * (hi - lo);
			if (openHi && !openLo)
				return lo - (-c - 0.5f) - inset * (hi - lo);
			return 0.0f;
		};
		Eigen::Vector3f out = t;
		out.x() -= (offset(e.u0, e.u1, cx_, obs_.width, box_.x, box_.open.left, box_.open.right) - sx * (e.u1 - e.u0)) *
			   t.z() / fx_;
		out.y() -= (offset(e.w0, e.w1, cy_, obs_.height, box_.y, box_.open.top, box_.open.bottom) - sy * (e.w1 - e.w0)) *
			   t.z() / fy_;
		return out;
	}

	// t moved along its ray to the depth where the extent (at t) fills the
	// window: the extent shrinks as the depth grows, by the geometric mean
	// of its two sides' ratios to the window's.
	Eigen::Vector3f sized(const Extent &e, const Eigen::Vector3f &t) const
	{
		if (e.behind || !(e.u1 > e.u0) || !(e.w1 > e.w0))
			return t;
		return t * std::sqrt((e.u1 - e.u0) / static_cast<float>(obs_.width) * (e.w1 - e.w0) /
				     static_cast<float>(obs_.height));
	}

	// Tallies at t, moved first along its ray by the median depth residual.
	Tally aligned(const TurnedView &v, Eigen::Vector3f &t, float *res) const
	{
		const int residuals = cfg_.maxShiftMm > 0 ? gather(v, t, res, nullptr, false).residuals : 0;
		if (residuals >= 8)
			// The median residual moves the model onto the surface the
			// sensor saw.
			t *= (t.z() + medianSelect(std::span<float>(res, static_cast<size_t>(residuals)))) / t.z();
		return tally(v, t);
	}

	// aligned() with one projection instead of two: after the move along
	// the ray every point's depth grows by the same median, so its residual
	// shrinks by it; the points' pixels, which the move shifts by a pixel at
	// most, are taken unchanged. For the coarse pass, which only ranks.
	Tally alignedOnce(const TurnedView &v, Eigen::Vector3f &t, float *res, float *all) const
	{
		if (!(cfg_.maxShiftMm > 0))
			return tally(v, t);
		const Gathered g = gather(v, t, res, all, true);
		Tally k;
		k.outside = g.outside;
		k.extent = g.extent;
		// Unmoved, every residual less +0: itself, bit for bit.
		float shift = 0.0f;
		if (g.residuals >= 8) {
			shift = medianSelect(std::span<float>(res, static_cast<size_t>(g.residuals)));
			t *= (t.z() + shift) / t.z();
		}
		for (int i = 0; i < g.compared; ++i)
			classifyIf(k, all[i] - shift, 1);
		return k;
	}

	float score(const Tally &k, int n) const
	{
		const int compared = k.in + k.out + k.occ;
		if (compared * 4 < n)
			return 0.0f;
		const float depth =
			depthAgreement(k.fit, k.in, k.out, k.occ, cfg_.outlierWeight, cfg_.occludedWeight);
		return depth * static_cast<float>(n - k.outside) / static_cast<float>(n) * boxAgreement(k);
	}

	// The full score's agreement with the box (boxAgreement() in
	// hypothesis_score.h) on the points' extent.
	float boxAgreement(const Tally &k) const
	{
		if (!(cfg_.boxWeight > 0))
			return 1.0f;
		const PixelExtent &e = k.extent;
		if (!(e.u1 >= e.u0) || !(e.w1 >= e.w0))
			return 0.0f;
		const float agreement = boxExtentAgreement(e.u0, e.w0, e.u1, e.w1, static_cast<float>(obs_.width),
							   static_cast<float>(obs_.height), cfg_.boxMargin,
							   cfg_.boxMinFill, box_.open);
		if (agreement >= 1.0f)
			return 1.0f;
		// In double, then rounded, as the full score: the same bits on
		// every target's libm (tests/estimation/golden_pose_test.cpp).
		return static_cast<float>(std::pow(static_cast<double>(agreement), static_cast<double>(cfg_.boxWeight)));
	}

private:
	const ViewSearchConfig &cfg_;
	ImageView<const float> obs_;
	float fx_, fy_, cx_, cy_;
	BoxAxes box_;
};

// Inserts p into the best-first list out[0, count) unless a proposal as
// good within `distinct` radians is there; worse ones nearby are dropped.
size_t insertProposal(std::span<ViewProposal> out, size_t count, const ViewProposal &p, double distinct)
{
	if (count == out.size() && p.score <= out[count - 1].score)
		return count;
	for (size_t j = 0; j < count; ++j)
		if (out[j].score >= p.score && rotationAngle(out[j].pose.R, p.pose.R) < distinct)
			return count;
	size_t kept = 0;
	for (size_t j = 0; j < count; ++j)
		if (rotationAngle(out[j].pose.R, p.pose.R) >= distinct)
			out[kept++] = out[j];
	count = kept;
	size_t pos = count;
	while (pos > 0 && out[pos - 1].score < p.score)
		--pos;
	if (pos >= out.size())
		return count;
	if (count < out.size())
		++count;
	std::move_backward(out.begin() + pos, out.begin() + count - 1, out.begin() + count);
	out[pos] = p;
	return count;
}

} // namespace

namespace {

// Order of coarse candidates: by score, ties by rotation index, a strict
// order so the kept set does not depend on which thread saw which rotation.
bool betterCandidate(const ViewCoarseCandidate &a, const ViewCoarseCandidate &b, int inplane)
{
	if (a.score != b.score)
		return a.score > b.score;
	return a.view * inplane + a.turn < b.view * inplane + b.turn;
}

// One thread's view: its points rotated by the view's rotation (a subset on
// a stride) and the translation they are tried at.
struct RotatedView {
	ViewPoints points;
	int m = 0;
	int view = -1;
	Eigen::Vector3f t0;
};

// Residual scratch of one evaluation.
struct EvalScratch {
	std::array<float, kMaxViewPoints> res, all, depths;
};

constexpr int kCoarseViewsPerTask = 8;
// The placements a rotation is tried at: its translation, the box-centred
// one and the edge insets (placed), and the box-centred one moved to either
// side (shifted).
constexpr int kPlaced = 1, kShifted = 2;
constexpr int kFinePerTask = 32;

// View v's points without the repeats of its last one that pad a view with
// fewer visible points.
int distinctPoints(std::span<const Eigen::Vector3f> pts)
{
	int m = std::min(static_cast<int>(pts.size()), kMaxViewPoints);
	while (m > 1 && pts[static_cast<size_t>(m - 1)] == pts[static_cast<size_t>(m - 2)])
		--m;
	return m;
}

} // namespace

int nearestView(const ViewTemplates &templates, const Pose &pose)
{
	if (templates.empty() || !(pose.t.z() > 0))
		return -1;
	const Eigen::Vector3f d = (-(pose.R.transpose() * pose.t).normalized()).cast<float>();
	const bool tabled = templates.directions.size() == static_cast<size_t>(templates.viewpoints);
	int best = 0;
	float bestDot = -2.0f;
	for (int v = 0; v < templates.viewpoints; ++v) {
		const Eigen::Vector3f dv = tabled ? templates.directions[static_cast<size_t>(v)]
						  : fibonacciDirection(v, templates.viewpoints).cast<float>();
		const float dot = dv.dot(d);
		if (dot > bestDot) {
			bestDot = dot;
			best = v;
		}
	}
	return best;
}

Eigen::Vector3d viewCentroid(const ViewTemplates &templates, int v)
{
	const std::span<const Eigen::Vector3f> pts = templates.view(v);
	const int m = distinctPoints(pts);
	Eigen::Vector3d sum = Eigen::Vector3d::Zero();
	for (int i = 0; i < m; ++i)
		sum += pts[static_cast<size_t>(i)].cast<double>();
	return m > 0 ? Eigen::Vector3d(sum / m) : sum;
}

float sparsePoseScore(const ViewTemplates &templates, int v, const ViewSearchConfig &config,
		      ImageView<const float> observed, const CameraIntrinsics &K, const Pose &pose, BoxAxes box,
		      Eigen::Vector3d &aligned)
{
	aligned = pose.t;
	if (templates.empty() || v < 0 || v >= templates.viewpoints || !(pose.t.z() > 1.0))
		return 0.0f;
	const std::span<const Eigen::Vector3f> pts = templates.view(v);
	const int m = distinctPoints(pts);
	ViewPoints posed;
	const Eigen::Matrix3f R = pose.R.cast<float>();
	for (int i = 0; i < m; ++i)
		posed.set(i, R * pts[static_cast<size_t>(i)]);
	const SparseScorer scorer(config, observed, K, box);
	std::array<float, kMaxViewPoints> res;
	Eigen::Vector3f t = pose.t.cast<float>();
	const float score = scorer.score(scorer.aligned(TurnedView{&posed, m, 1.0f, 0.0f}, t, res.data()), m);
	aligned = t.cast<double>();
	return score;
}

size_t searchViews(const ViewTemplates &templates, const ViewSearchConfig &config,
		   ImageView<const float> observed, const CameraIntrinsics &K,
		   const Eigen::Vector3d &centre, std::span<ViewProposal> out, BoxAxes box,
		   float anchorDepth, WorkerPool *pool, ViewSearchWorkspace workspace)
{
	const int total = viewSearchSize(templates, config);
	if (total == 0 || config.inplane > kMaxInplane || out.empty() || !(anchorDepth > 0 || centre.z() > 1.0))
		return 0;
	const int n = std::min(templates.pointsPerView, kMaxViewPoints);
	const SparseScorer scorer(config, observed, K, box);
	const Eigen::Vector3f centreF = centre.cast<float>();
	const double distinct = config.distinctDeg * M_PI / 180.0;
	const bool centring = config.boxCentre && (box.x || box.y || box.open.left != box.open.right ||
						   box.open.top != box.open.bottom);
	const int inplane = config.inplane;
	const bool centredOnly = !config.coarseAtCentre && centring && anchorDepth > 0 && box.x && box.y;
	// Placements inside a one-sided clip (edgeInsets).
	const bool edgePlaced = centring && (box.open.left != box.open.right || box.open.top != box.open.bottom);
	const int insets = edgePlaced ? std::clamp(config.edgeInsets, 0, 8) : 0;

	// The view's points (already rotated by the view) turned in-plane; the
	// turns' cosines and sines once per search, not once per rotation.
	std::array<std::array<float, 2>, kMaxInplane> turns;
	for (int turn = 0; turn < inplane; ++turn) {
		const double angle = 2.0 * M_PI * turn / inplane;
		turns[static_cast<size_t>(turn)] = {static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle))};
	}
	auto turnedView = [&](const ViewPoints *pts, int m, int turn) {
		const auto &cs = turns[static_cast<size_t>(turn)];
		return TurnedView{pts, m, cs[0], cs[1]};
	};
	// Score of one rotation of view r, at its translation and the
	// box-centred ones (inside a one-sided clip, shifted on trusted axes);
	// t gets the best one's.
	const float shift = centring ? config.centreShiftShare : 0.0f;
	const bool bySize = config.placeBySize && box.x && box.y;
	const float shiftX[4] = {shift, -shift, 0, 0}, shiftY[4] = {0, 0, shift, -shift};
	// `placements`: kPlaced, kShifted or both.
	auto evaluate = [&](const RotatedView &r, int turn, Eigen::Vector3f &t, bool coarse, EvalScratch &s,
			    int placements = kPlaced | kShifted) {
		const TurnedView tv = turnedView(&r.points, r.m, turn);
		const bool placed = placements & kPlaced, shifted = placements & kShifted;
		float best = -1.0f;
		auto consider = [&](Eigen::Vector3f at) {
			const Tally k = coarse ? scorer.alignedOnce(tv, at, s.res.data(), s.all.data())
					       : scorer.aligned(tv, at, s.res.data());
			const float score = scorer.score(k, r.m);
			if (score > best) {
				best = score;
				t = at;
			}
		};
		// The box-centred placement at `at` shifted to either side on the
		// axes the box is trusted on.
		auto considerShifted = [&](const SparseScorer::Extent &extent, const Eigen::Vector3f &at) {
			for (int k = 0; k < 4 && shift > 0 && shifted; ++k)
				if (k < 2 ? box.x : box.y)
					consider(scorer.centred(extent, at, 0.0f, shiftX[k], shiftY[k]));
		};
		if (bySize) {
			// Filling the box, and as far again as a box drawn 10 % larger
			// than the object puts it.
			const Eigen::Vector3f filling = scorer.sized(scorer.extent(tv, r.t0), r.t0);
			for (const float margin : {1.0f, 1.1f}) {
				const Eigen::Vector3f at = filling * margin;
				const auto extent = scorer.extent(tv, at);
				if (placed)
					consider(scorer.centred(extent, at));
				considerShifted(extent, at);
			}
			return best;
		}
		if (placed && !(coarse && centredOnly))
			consider(r.t0);
		if (!centring)
			return best;
		const auto extent = scorer.extent(tv, r.t0);
		for (int k = 0; k <= insets && placed; ++k)
			consider(scorer.centred(extent, r.t0, static_cast<float>(k) * config.edgeInsetShare));
		considerShifted(extent, r.t0);
		return best;
	};
	// Whether any placement is a shifted one (the coarse pass then tries
	// them on its best rotations only).
	const bool shifting = config.coarseShifted > 0 && centring && shift > 0 && (box.x || box.y);
	auto rotateView = [&](RotatedView &r, int v, int stride, EvalScratch &s) {
		const Eigen::Matrix3f r0 = viewRotation(templates, 1, v, 0).cast<float>();
		const std::span<const Eigen::Vector3f> pts = templates.view(v);
		int m = 0;
		for (int i = 0; i < n; i += stride)
			r.points.set(m++, r0 * pts[i]);
		r.m = m;
		r.view = v;
		r.t0 = centreF;
		if (anchorDepth > 0 && m > 0) {
			// In-plane turns keep every point's depth: one median per view.
			std::copy_n(r.points.z.begin(), m, s.depths.begin());
			r.t0.z() = anchorDepth - medianSelect(std::span<float>(s.depths.data(), static_cast<size_t>(m)));
		}
	};
	auto runTasks = [&](int tasks, auto &&task) {
		if (pool)
			pool->run(tasks, task);
		else
			for (int i = 0; i < tasks; ++i)
				task(i, 0);
	};
	// The last pass proposes into `wide` when the lateral climb is on, into
	// `out` directly otherwise.
	const bool climb = config.lateralStepMm > 0 || config.rotationStepDeg > 0;
	std::array<ViewProposal, kMaxRefineTop> wideStorage;
	const std::span<ViewProposal> wide =
		climb ? std::span<ViewProposal>(wideStorage.data(),
						static_cast<size_t>(std::clamp(config.refineTop, 1, kMaxRefineTop)))
		      : out;
	size_t count = 0;
	auto propose = [&](int v, int turn, float score, const Eigen::Vector3f &t) {
		if (score <= 0 || (count == wide.size() && score <= wide[count - 1].score))
			return;
		ViewProposal p;
		p.score = score;
		p.pose.R = viewRotation(templates, inplane, v, turn);
		p.pose.t = t.cast<double>();
		p.view = v;
		p.turn = turn;
		count = insertProposal(wide, count, p, distinct);
	};
	// Hill climb of one proposal's sparse score: sideways moves and, when
	// rotationStepDeg > 0, small turns about the camera axes through the
	// model origin (the template grid is ~10 deg coarse: the truth's
	// nearest template can score below a wrong rotation's); depth
	// re-aligned at every step. A trial turn is scored on the points of
	// the view the climb stands on (a turn of a few degrees hardly changes
	// which points are visible); once the turns have tilted the pose
	// nearer another view, the climb stands on that one, with its points
	// and the pose's honest score on them. Without that the climb drifts
	// tens of degrees scoring points the pose hides (behind the model), and
	// finds the poses that lay those on whatever they fit: an occluder, the
	// wall.
	auto climbSideways = [&](ViewProposal &p, RotatedView &r, EvalScratch &s) {
		rotateView(r, p.view, 1, s);
		const TurnedView base = turnedView(&r.points, r.m, p.turn);
		const bool turning = config.rotationStepDeg > 0;
		// With turns: the points in camera axes (turned in-plane too),
		// the current one in `cur`, a trial in `trial`.
		ViewPoints cur, trial;
		int curN = r.m;
		if (turning)
			for (int i = 0; i < r.m; ++i) {
				const Eigen::Vector3f a = r.points.at(i);
				cur.set(i, {base.c * a.x() - base.s * a.y(), base.s * a.x() + base.c * a.y(), a.z()});
			}
		Eigen::Matrix3f turned = Eigen::Matrix3f::Identity();
		Eigen::Vector3f t = p.pose.t.cast<float>();
		float best = p.score;
		// After a turn: the view nearest the turned pose, its points put in
		// camera axes and the pose scored on them, when it is another.
		auto standOnNearestView = [&]() {
			Pose at;
			at.R = turned.cast<double>() * p.pose.R;
			at.t = t.cast<double>();
			const int v = nearestView(templates, at);
			if (v < 0 || v == p.view)
				return;
			const std::span<const Eigen::Vector3f> pts = templates.view(v);
			curN = std::min(distinctPoints(pts), n);
			const Eigen::Matrix3f R = at.R.cast<float>();
			for (int i = 0; i < curN; ++i)
				cur.set(i, R * pts[static_cast<size_t>(i)]);
			p.view = v;
			const TurnedView moved{&cur, curN, 1.0f, 0.0f};
			best = scorer.score(scorer.aligned(moved, t, s.res.data()), curN);
		};
		const float lateral = config.lateralStepMm, angle = config.rotationStepDeg * static_cast<float>(M_PI / 180.0);
		for (int level = 0; level < 3; ++level) {
			const float step = lateral * std::ldexp(1.0f, -level);
			const float turn = angle * std::ldexp(1.0f, -level);
			for (int pass = 0; pass < 3; ++pass) {
				const TurnedView here = turning ? TurnedView{&cur, curN, 1.0f, 0.0f} : base;
				const TurnedView trialView{&trial, curN, 1.0f, 0.0f};
				Eigen::Vector3f bestT = t;
				int bestMove = -1;
				for (int d = 0; d < 4 && step > 0; ++d) {
					Eigen::Vector3f c = t;
					c[d / 2] += (d % 2 ? step : -step);
					const float sc = scorer.score(scorer.aligned(here, c, s.res.data()), here.n);
					if (sc > best) {
						best = sc;
						bestT = c;
						bestMove = d;
					}
				}
				Eigen::Matrix3f bestD = Eigen::Matrix3f::Identity();
				for (int d = 0; d < 6 && turning; ++d) {
					const Eigen::Matrix3f D =
						Eigen::AngleAxisf(d % 2 ? turn : -turn, Eigen::Vector3f::Unit(d / 2))
							.toRotationMatrix();
					for (int i = 0; i < curN; ++i)
						trial.set(i, D * cur.at(i));
					Eigen::Vector3f c = t;
					const float sc = scorer.score(scorer.aligned(trialView, c, s.res.data()), trialView.n);
					if (sc > best) {
						best = sc;
						bestT = c;
						bestMove = 4 + d;
						bestD = D;
					}
				}
				if (bestMove < 0)
					break;
				t = bestT;
				if (bestMove >= 4) {
					for (int i = 0; i < curN; ++i)
						cur.set(i, bestD * cur.at(i));
					turned = bestD * turned;
					standOnNearestView();
				}
			}
		}
		p.score = best;
		p.pose.t = t.cast<double>();
		if (turning)
			p.pose.R = turned.cast<double>() * p.pose.R;
	};
	// The climbed proposals, best distinct first, into `out`. Each climbs
	// on its own, so they are spread over the threads.
	auto finish = [&]() {
		if (!climb)
			return count;
		runTasks(static_cast<int>(count), [&](int i, int) {
			RotatedView r;
			EvalScratch s;
			climbSideways(wide[static_cast<size_t>(i)], r, s);
		});
		std::sort(wide.begin(), wide.begin() + count,
			  [](const ViewProposal &a, const ViewProposal &b) { return a.score > b.score; });
		size_t kept = 0;
		for (size_t i = 0; i < count; ++i)
			kept = insertProposal(out, kept, wide[i], distinct);
		return kept;
	};

	const int stride = config.coarsePoints > 0 ? std::max(1, n / config.coarsePoints) : 1;
	const int keep = std::clamp(config.coarseKeep, 1, kMaxCoarseKeep);
	if (stride == 1) {
		// One pass on all points (not the default): in order, one thread.
		RotatedView r;
		EvalScratch s;
		for (int v = 0; v < templates.viewpoints; ++v) {
			rotateView(r, v, 1, s);
			for (int turn = 0; turn < inplane; ++turn) {
				Eigen::Vector3f t;
				const float score = evaluate(r, turn, t, false, s);
				propose(v, turn, score, t);
			}
		}
		return finish();
	}

	// Without a workspace: one thread on stack storage.
	std::array<ViewCoarseCandidate, kMaxCoarseKeep> ownHeap;
	std::array<ViewFineResult, kMaxCoarseKeep> ownFine;
	const int threads = pool && workspace.heaps.size() >= viewSearchHeapSize(pool->threads()) &&
				    workspace.fine.size() >= static_cast<size_t>(kMaxCoarseKeep)
			    ? pool->threads()
			    : 1;
	if (threads == 1)
		pool = nullptr;
	const std::span<ViewCoarseCandidate> heaps =
		threads > 1 ? workspace.heaps : std::span<ViewCoarseCandidate>(ownHeap);
	const std::span<ViewFineResult> fine = threads > 1 ? workspace.fine : std::span<ViewFineResult>(ownFine);
	auto better = [inplane](const ViewCoarseCandidate &a, const ViewCoarseCandidate &b) {
		return betterCandidate(a, b, inplane);
	};

	// Coarse pass: each thread keeps a min-heap of its best `wanted`
	// rotations; with coarseShifted only at their placed placements, and
	// only the best `wanted` of those try the shifted ones.
	const int wanted = shifting ? std::clamp(keep * config.coarseShifted, keep, kMaxCoarseKeep) : keep;
	const int firstPlacements = shifting ? kPlaced : kPlaced | kShifted;
	std::array<size_t, WorkerPool::kMaxThreads> held{};
	const int coarseTasks = (templates.viewpoints + kCoarseViewsPerTask - 1) / kCoarseViewsPerTask;
	runTasks(coarseTasks, [&](int task, int thread) {
		ViewCoarseCandidate *heap = heaps.data() + static_cast<size_t>(thread) * kMaxCoarseKeep;
		size_t &h = held[static_cast<size_t>(thread)];
		RotatedView r;
		EvalScratch s;
		const int v1 = std::min(templates.viewpoints, (task + 1) * kCoarseViewsPerTask);
		for (int v = task * kCoarseViewsPerTask; v < v1; ++v) {
			rotateView(r, v, stride, s);
			for (int turn = 0; turn < inplane; ++turn) {
				Eigen::Vector3f t;
				const ViewCoarseCandidate c{evaluate(r, turn, t, true, s, firstPlacements), v, turn};
				if (c.score <= 0)
					continue;
				if (h < static_cast<size_t>(wanted)) {
					heap[h++] = c;
					std::push_heap(heap, heap + h, better);
				} else if (better(c, heap[0])) {
					std::pop_heap(heap, heap + h, better);
					heap[h - 1] = c;
					std::push_heap(heap, heap + h, better);
				}
			}
		}
	});
	// The threads' heaps side by side; their best `wanted` are the best of all.
	size_t held0 = held[0];
	for (int th = 1; th < threads; ++th)
		for (size_t i = 0; i < held[static_cast<size_t>(th)]; ++i)
			heaps[held0++] = heaps[static_cast<size_t>(th) * kMaxCoarseKeep + i];
	ViewCoarseCandidate *cand = heaps.data();
	if (held0 > static_cast<size_t>(wanted)) {
		std::nth_element(cand, cand + wanted, cand + held0, better);
		held0 = static_cast<size_t>(wanted);
	}
	// Each of the first `count` candidates, sorted by rotation, evaluated
	// by eval(i, rotated view, scratch) on its view's points (every
	// stride-th), spread over the threads; each view is rotated once per
	// task.
	auto forCandidates = [&](size_t count, int pointStride, auto &&eval) {
		std::sort(cand, cand + count, [](const ViewCoarseCandidate &a, const ViewCoarseCandidate &b) {
			return a.view != b.view ? a.view < b.view : a.turn < b.turn;
		});
		const int tasks = static_cast<int>((count + kFinePerTask - 1) / kFinePerTask);
		runTasks(tasks, [&](int task, int) {
			RotatedView r;
			EvalScratch s;
			const size_t i1 = std::min(count, static_cast<size_t>(task + 1) * kFinePerTask);
			for (size_t i = static_cast<size_t>(task) * kFinePerTask; i < i1; ++i) {
				if (cand[i].view != r.view)
					rotateView(r, cand[i].view, pointStride, s);
				eval(i, r, s);
			}
		});
	};
	// Their shifted placements; a rotation keeps its better score.
	if (shifting)
		forCandidates(held0, stride, [&](size_t i, const RotatedView &r, EvalScratch &s) {
			Eigen::Vector3f t;
			cand[i].score = std::max(cand[i].score, evaluate(r, cand[i].turn, t, true, s, kShifted));
		});
	if (held0 > static_cast<size_t>(keep)) {
		std::nth_element(cand, cand + keep, cand + held0, better);
		held0 = static_cast<size_t>(keep);
	}
	// Fine pass on all points; results by candidate, proposed in rotation
	// order.
	forCandidates(held0, 1, [&](size_t i, const RotatedView &r, EvalScratch &s) {
		fine[i].score = evaluate(r, cand[i].turn, fine[i].t, false, s);
	});
	for (size_t i = 0; i < held0; ++i)
		propose(cand[i].view, cand[i].turn, fine[i].score, fine[i].t);
	return finish();
}

} // namespace ihf
