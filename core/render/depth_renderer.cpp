// SPDX-License-Identifier: MIT
// Software depth rasteriser.
//
// Coverage uses integer edge functions on vertices snapped to 1/256 pixel,
// so the top-left rule is exact, neighbouring triangles neither overlap nor
// leave cracks, and stepping from pixel to pixel accumulates no rounding.
// Depth does not come from the snapped vertices: 1/z of the triangle's plane
// is an affine function of the image coordinates, evaluated in double at each
// covered pixel centre from its absolute image coordinates. Both facts make a
// pixel's value independent of the window it is rendered into.

#include "core/render/depth_renderer.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <string>

namespace ihf {

namespace {

constexpr int kSubBits = 8;
constexpr int64_t kSub = int64_t{1} << kSubBits;

// Vertices projecting beyond this many pixels from the origin are clipped in
// camera space against these lines, keeping every fixed-point product well
// inside int64 (coordinates < 2^23, products < 2^48).
constexpr double kGuard = 16384.0;
static_assert(DepthRenderer::kMaxWindowCoord <= kGuard / 2, "guard clipping must stay outside every window");

// Marks a vertex whose snapped position is not usable (see VertexFlag).
constexpr int32_t kNoScreen = INT32_MIN;

enum VertexFlag : uint8_t {
	kBehindNear = 1,
	kOutsideGuard = 2,
	kNotFinite = 4,
};

struct Snapped {
	int64_t x, y; // image position in 1/kSub pixel
};

// Round to nearest, ties to even, for |x| < 2^51: adding 1.5 * 2^52 leaves
// no fraction bits. Inline, unlike floor()/lrint() calls without fast-math.
inline int64_t roundNearest(double x)
{
	constexpr double kMagic = 6755399441055744.0;
	return static_cast<int64_t>((x + kMagic) - kMagic);
}

inline Snapped snap(double u, double v)
{
	return {roundNearest(u * kSub), roundNearest(v * kSub)};
}

// 1/z on the image as an affine function: invZ(u, v) = a u + b v + c.
// zMin/zMax bound the (clipped) triangle, guarding against snapping making a
// nearly edge-on triangle cover pixels where its plane is far off.
struct DepthPlane {
	double a, b, c;
	float zMin, zMax;
};

struct Target {
	float *depth;
	std::ptrdiff_t depthStride;
	uint16_t *label;
	std::ptrdiff_t labelStride;
	uint16_t labelValue;
	int x0, y0; // window origin, image coordinates
	int x1, y1; // last pixel of the window (inclusive), image coordinates
};

// Plane through three camera-space points; false if degenerate or seen
// edge-on through the camera centre.
bool makePlane(const Eigen::Vector3d &p0, const Eigen::Vector3d &p1, const Eigen::Vector3d &p2,
	       const CameraIntrinsics &K, DepthPlane &plane)
{
	const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
	const double d = n.dot(p0);
	// Ray ((u - cx)/fx, (v - cy)/fy, 1) meets n.X = d at Z = d / (n.ray).
	if (!(d * d > 1e-24 * n.squaredNorm() * p0.squaredNorm()))
		return false;
	const double invD = 1.0 / d;
	const double nx = n.x() / K.fx, ny = n.y() / K.fy;
	plane.a = nx * invD;
	plane.b = ny * invD;
	plane.c = (n.z() - nx * K.cx - ny * K.cy) * invD;
	return true;
}

// The depth plane of one mesh triangle, computed on first use: most
// triangles of a distant mesh cover no pixel centre and never need it.
class LazyPlane
{
public:
	LazyPlane(const Eigen::Vector3f *camera, const uint32_t *face, const CameraIntrinsics &K)
		: camera_(camera), face_(face), K_(K) {}

	// For clipped triangles: the z range of the clipped polygon.
	void setZRange(float zMin, float zMax)
	{
		zRangeSet_ = true;
		plane_.zMin = zMin;
		plane_.zMax = zMax;
	}

	const DepthPlane *get()
	{
		if (state_ == 0) {
			const Eigen::Vector3f &p0 = camera_[face_[0]], &p1 = camera_[face_[1]], &p2 = camera_[face_[2]];
			state_ = makePlane(p0.cast<double>(), p1.cast<double>(), p2.cast<double>(), K_, plane_) ? 1 : -1;
			if (!zRangeSet_) {
				plane_.zMin = std::min(p0.z(), std::min(p1.z(), p2.z()));
				plane_.zMax = std::max(p0.z(), std::max(p1.z(), p2.z()));
			}
		}
		return state_ > 0 ? &plane_ : nullptr;
	}

	// The plane if get() already succeeded, else null.
	const DepthPlane *ready() const { return state_ > 0 ? &plane_ : nullptr; }

private:
	const Eigen::Vector3f *camera_; // camera coordinates of the mesh vertices
	const uint32_t *face_;
	const CameraIntrinsics &K_;
	bool zRangeSet_ = false; // else taken from the three vertices
	int state_ = 0; // 0 not yet, 1 valid, -1 degenerate
	DepthPlane plane_; // set by get() (and setZRange())
};

// 1/z at pixel centre (x, y) is a x + rowTerm(y). Kept in one place so every
// path computes a pixel bit-identically.
inline double rowTerm(const DepthPlane &p, int y)
{
	return p.b * y + p.c;
}

// Depth-tests and writes one covered pixel; true if written.
inline bool shade(const DepthPlane &p, int x, double rowC, float *drow, uint16_t *lrow, uint16_t labelValue)
{
	const double invZ = p.a * x + rowC;
	if (!(invZ > 0.0))
		return false;
	const float z = std::clamp(static_cast<float>(1.0 / invZ), p.zMin, p.zMax);
	float &d = drow[x];
	if (d == 0.0f || z < d) {
		d = z;
		if (lrow)
			lrow[x] = labelValue;
		return true;
	}
	return false;
}

/*
 * One triangle in snapped image coordinates. bound() finds the pixel centres
 * of the window inside its bounding box; then either scanSingle() tests the
 * only one, or edges() sets up the edge functions and scan() walks them.
 * Both apply the same rule, so which one runs (it depends on the window)
 * never changes a pixel.
 */
class Triangle
{
public:
	// Pixel centres of the window inside the bounding box [minX, maxX] x
	// [minY, maxY] (snapped units); false if there are none, the cheapest
	// reject for sub-pixel triangles.
	template<typename Int>
	bool bound(Int minX, Int maxX, Int minY, Int maxY, const Target &t)
	{
		// Centres x with minX <= x * kSub <= maxX (arithmetic shifts floor).
		xs_ = std::max(t.x0, static_cast<int>((minX + static_cast<Int>(kSub - 1)) >> kSubBits));
		xe_ = std::min(t.x1, static_cast<int>(maxX >> kSubBits));
		ys_ = std::max(t.y0, static_cast<int>((minY + static_cast<Int>(kSub - 1)) >> kSubBits));
		ye_ = std::min(t.y1, static_cast<int>(maxY >> kSubBits));
		return xs_ <= xe_ && ys_ <= ye_;
	}

	// Orients the triangle and sets up its edge functions at the first
	// centre of the bound; false if it has zero area.
	bool edges(Snapped v0, Snapped v1, Snapped v2)
	{
		const int64_t area = (v1.x - v0.x) * (v2.y - v0.y) - (v1.y - v0.y) * (v2.x - v0.x);
		if (area == 0)
			return false;
		if (area < 0)
			std::swap(v1, v2);
		edge(v0, v1, 0);
		edge(v1, v2, 1);
		edge(v2, v0, 2);
		return true;
	}

	bool setup(Snapped v0, Snapped v1, Snapped v2, const Target &t)
	{
		return bound(std::min(v0.x, std::min(v1.x, v2.x)), std::max(v0.x, std::max(v1.x, v2.x)),
			     std::min(v0.y, std::min(v1.y, v2.y)), std::max(v0.y, std::max(v1.y, v2.y)), t) &&
		       edges(v0, v1, v2);
	}

	// The bound holds a single pixel centre, the usual case for the many
	// sub-pixel triangles of a distant mesh.
	bool single() const { return xs_ == xe_ && ys_ == ye_; }

	// Same coverage rule as edges() + scan(), evaluated at the one centre
	// directly. Returns the depth-test passes, or -1 if degenerate. With a
	// single centre in the box every vertex is within 2 pixels (512 units)
	// of it, so 32-bit products are exact.
	int scanSingle(const int32_t (&sx)[3], const int32_t (&sy)[3], LazyPlane &lazy, const Target &t) const
	{
		const int32_t px = xs_ * static_cast<int32_t>(kSub), py = ys_ * static_cast<int32_t>(kSub);
		int32_t ax = sx[0] - px, ay = sy[0] - py;
		int32_t bx = sx[1] - px, by = sy[1] - py;
		int32_t cx = sx[2] - px, cy = sy[2] - py;
		const int32_t area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
		if (area == 0)
			return -1;
		if (area < 0) {
			std::swap(bx, cx);
			std::swap(by, cy);
		}
		// Edge function of a->b at the centre (the origin), with the top-left
		// rule for centres exactly on the edge.
		auto inside = [](int32_t ax, int32_t ay, int32_t bx, int32_t by) {
			const int32_t e = ax * by - ay * bx;
			const int32_t dx = bx - ax, dy = by - ay;
			return e > 0 || (e == 0 && (dy < 0 || (dy == 0 && dx > 0)));
		};
		if (!inside(ax, ay, bx, by) || !inside(bx, by, cx, cy) || !inside(cx, cy, ax, ay))
			return 0;
		const DepthPlane *plane = lazy.get();
		if (!plane)
			return -1;
		float *drow = t.depth + (ys_ - t.y0) * t.depthStride - t.x0;
		uint16_t *lrow = t.label ? t.label + (ys_ - t.y0) * t.labelStride - t.x0 : nullptr;
		return shade(*plane, xs_, rowTerm(*plane, ys_), drow, lrow, t.labelValue);
	}

	// Returns the depth-test passes, or -1 if the plane is degenerate (seen
	// edge-on).
	int scan(LazyPlane &lazy, const Target &t) const
	{
		int written = 0;
		const DepthPlane *plane = lazy.ready();
		int64_t r0 = e_[0], r1 = e_[1], r2 = e_[2];
		for (int y = ys_; y <= ye_; ++y) {
			int64_t e0 = r0, e1 = r1, e2 = r2;
			float *drow = t.depth + (y - t.y0) * t.depthStride - t.x0;
			uint16_t *lrow = t.label ? t.label + (y - t.y0) * t.labelStride - t.x0 : nullptr;
			double rowC = plane ? rowTerm(*plane, y) : 0.0;
			bool seen = false;
			for (int x = xs_; x <= xe_; ++x, e0 += dx_[0], e1 += dx_[1], e2 += dx_[2]) {
				if ((e0 | e1 | e2) < 0) {
					// Convex: once out after being in, the row is done.
					if (seen)
						break;
					continue;
				}
				seen = true;
				if (!plane) {
					plane = lazy.get();
					if (!plane)
						return -1;
					rowC = rowTerm(*plane, y);
				}
				written += shade(*plane, x, rowC, drow, lrow, t.labelValue);
			}
			r0 += dy_[0];
			r1 += dy_[1];
			r2 += dy_[2];
		}
		return written;
	}

private:
	// Edge a->b with the interior on its positive side. Top-left rule: a
	// centre exactly on an edge belongs to the triangle only for a top edge
	// (horizontal, interior below) or a left edge (interior to its right),
	// done by biasing the other edges by -1 and testing >= 0.
	void edge(Snapped a, Snapped b, int i)
	{
		const int64_t dx = b.x - a.x;
		const int64_t dy = b.y - a.y;
		const bool topLeft = dy < 0 || (dy == 0 && dx > 0);
		const int64_t px = static_cast<int64_t>(xs_) * kSub;
		const int64_t py = static_cast<int64_t>(ys_) * kSub;
		e_[i] = dx * (py - a.y) - dy * (px - a.x) - (topLeft ? 0 : 1);
		dx_[i] = -dy * kSub;
		dy_[i] = dx * kSub;
	}

	int xs_ = 0, xe_ = -1, ys_ = 0, ye_ = -1;
	int64_t e_[3] = {};
	int64_t dx_[3] = {};
	int64_t dy_[3] = {};
};

// Branch-free so it vectorises: a pass over 45k faces costs microseconds.
// Kept out of line: inlined into render() GCC 12 leaves it scalar.
[[gnu::noinline]] bool anyIndexAtLeast(const uint32_t *idx, size_t count, uint32_t n)
{
	uint32_t bad = 0;
	for (size_t i = 0; i < count; ++i)
		bad |= static_cast<uint32_t>(idx[i] >= n);
	return bad != 0;
}

// Polygon vertex during clipping: camera coordinates and, while it is still
// an unclipped mesh vertex, its index (to reuse its cached snapped position,
// so clipped and unclipped neighbours share vertices exactly).
struct ClipVertex {
	Eigen::Vector3d p;
	int64_t index;
};

constexpr int kMaxPolygon = 3 + 1 + 4 + 1;

// Sutherland-Hodgman against one plane, f(p) <= 0 inside. Intersections are
// computed from the inside towards the outside endpoint whichever way the
// polygon runs, so two triangles sharing an edge get identical points.
template<typename F>
int clipPolygon(const ClipVertex *in, int n, ClipVertex *out, F f)
{
	int m = 0;
	for (int i = 0; i < n; ++i) {
		const ClipVertex &a = in[i];
		const ClipVertex &b = in[(i + 1) % n];
		const double fa = f(a.p);
		const double fb = f(b.p);
		const bool aIn = fa <= 0.0;
		const bool bIn = fb <= 0.0;
		if (aIn)
			out[m++] = a;
		if (aIn != bIn) {
			const ClipVertex &pin = aIn ? a : b;
			const ClipVertex &pout = aIn ? b : a;
			const double fi = aIn ? fa : fb;
			const double fo = aIn ? fb : fa;
			const double s = fi / (fi - fo);
			out[m++] = {pin.p + s * (pout.p - pin.p), -1};
		}
	}
	return m;
}

} // namespace

DepthRenderer::DepthRenderer(size_t maxVertices)
{
	reserve(maxVertices);
}

template<typename A>
bool DepthRenderer::carve(A &arena, size_t maxVertices)
{
	return arenaTake(arena, screen_, maxVertices) && arenaTake(arena, flags_, maxVertices) &&
	       arenaTake(arena, camera_, maxVertices);
}

size_t DepthRenderer::arenaBytes(size_t maxVertices)
{
	ArenaSizer sizer;
	DepthRenderer scratch;
	scratch.carve(sizer, maxVertices);
	return sizer.bytes;
}

void DepthRenderer::reserve(size_t maxVertices)
{
	if (maxVertices <= capacity_)
		return;
	auto arena = Arena::create(arenaBytes(maxVertices));
	if (!arena)
		return; // keeps the old capacity; render() reports kCapacity
	own_ = std::move(*arena);
	(void)reserve(maxVertices, own_);
}

Status DepthRenderer::reserve(size_t maxVertices, Arena &arena)
{
	if (!carve(arena, maxVertices)) {
		screen_ = {};
		flags_ = {};
		camera_ = {};
		capacity_ = 0;
		return makeError(Errc::kCapacity, "DepthRenderer: arena too small for the vertex limit");
	}
	capacity_ = maxVertices;
	return {};
}

Expected<RenderStats> DepthRenderer::render(const Mesh &mesh, const Pose &pose, const CameraIntrinsics &K,
					    ImageView<float> depth, ImageView<uint16_t> label, uint16_t labelValue,
					    RenderWindow window)
{
	const size_t nv = mesh.vertices.size();
	if (nv > capacity_)
		return makeError(Errc::kCapacity, "DepthRenderer: mesh has " + std::to_string(nv) +
							  " vertices, capacity is " + std::to_string(capacity_));
	if (!(K.fx > 0 && K.fy > 0 && std::isfinite(K.fx) && std::isfinite(K.fy) && std::isfinite(K.cx) &&
	      std::isfinite(K.cy)))
		return makeError(Errc::kInvalidArgument, "DepthRenderer: invalid intrinsics");
	if (!(near_ > 0.0f) || !std::isfinite(near_))
		return makeError(Errc::kInvalidArgument, "DepthRenderer: near plane must be > 0");
	if (!pose.R.allFinite() || !pose.t.allFinite())
		return makeError(Errc::kInvalidArgument, "DepthRenderer: pose is not finite");
	if (depth.data == nullptr || depth.empty() || depth.stride < depth.width)
		return makeError(Errc::kInvalidArgument, "DepthRenderer: empty depth buffer");
	if (label.data && (label.width != depth.width || label.height != depth.height || label.stride < label.width))
		return makeError(Errc::kInvalidArgument, "DepthRenderer: label buffer size differs from depth buffer");
	if (window.x0 < -kMaxWindowCoord || window.y0 < -kMaxWindowCoord ||
	    window.x0 > kMaxWindowCoord - depth.width || window.y0 > kMaxWindowCoord - depth.height)
		return makeError(Errc::kInvalidArgument, "DepthRenderer: window outside the supported image range");
	// Validate indices up front so a bad mesh leaves the buffers untouched.
	static_assert(sizeof(mesh.faces[0]) == 3 * sizeof(uint32_t), "faces must be packed index triples");
	if (nv <= UINT32_MAX && !mesh.faces.empty()) {
		if (anyIndexAtLeast(mesh.faces.front().data(), 3 * mesh.faces.size(), static_cast<uint32_t>(nv)))
			return makeError(Errc::kOutOfRange, "DepthRenderer: face index past " + std::to_string(nv) +
								    " vertices");
	}

	RenderStats stats;
	const Target target{depth.data,
			    depth.stride,
			    label.data,
			    label.stride,
			    labelValue,
			    window.x0,
			    window.y0,
			    window.x0 + depth.width - 1,
			    window.y0 + depth.height - 1};
	const double nearD = near_;

	// Vertices to camera coordinates, and snapped image positions.
	const Eigen::Matrix3d &R = pose.R;
	const Eigen::Vector3d &t = pose.t;
	for (size_t i = 0; i < nv; ++i) {
		const Eigen::Vector3d p = R * mesh.vertices[i].cast<double>() + t;
		camera_[i] = p.cast<float>();
		ScreenVertex &sv = screen_[i];
		uint8_t flags = 0;
		if (!std::isfinite(p.x() + p.y() + p.z())) {
			flags = kNotFinite;
		} else if (p.z() < nearD) {
			flags = kBehindNear;
		} else {
			const double invZ = 1.0 / p.z();
			const double u = K.fx * p.x() * invZ + K.cx;
			const double v = K.fy * p.y() * invZ + K.cy;
			if (std::abs(u) < kGuard && std::abs(v) < kGuard) {
				const Snapped s = snap(u, v);
				sv.sx = static_cast<int32_t>(s.x);
				sv.sy = static_cast<int32_t>(s.y);
			} else {
				flags = kOutsideGuard;
			}
		}
		if (flags)
			sv.sx = sv.sy = kNoScreen;
		flags_[i] = flags;
	}

	auto project = [&K](const Eigen::Vector3d &p) {
		return snap(K.fx * p.x() / p.z() + K.cx, K.fy * p.y() / p.z() + K.cy);
	};

	Triangle tri;
	for (const auto &f : mesh.faces) {
		const ScreenVertex &a = screen_[f[0]];
		const ScreenVertex &b = screen_[f[1]];
		const ScreenVertex &c = screen_[f[2]];
		if (a.sx != kNoScreen && b.sx != kNoScreen && c.sx != kNoScreen) {
			// 32-bit bounding box: snapped positions are below 2^23.
			if (!tri.bound(std::min(a.sx, std::min(b.sx, c.sx)), std::max(a.sx, std::max(b.sx, c.sx)),
				       std::min(a.sy, std::min(b.sy, c.sy)), std::max(a.sy, std::max(b.sy, c.sy)), target)) {
				++stats.trianglesCulled;
				continue;
			}
			if (cullBackFaces_ && int64_t{b.sx - a.sx} * (c.sy - a.sy) - int64_t{b.sy - a.sy} * (c.sx - a.sx) > 0) {
				++stats.trianglesCulled;
				continue;
			}
			LazyPlane plane(camera_.data(), f.data(), K);
			int written;
			if (tri.single()) {
				written = tri.scanSingle({a.sx, b.sx, c.sx}, {a.sy, b.sy, c.sy}, plane, target);
			} else {
				if (!tri.edges({a.sx, a.sy}, {b.sx, b.sy}, {c.sx, c.sy})) {
					++stats.trianglesCulled;
					continue;
				}
				written = tri.scan(plane, target);
			}
			if (written < 0) {
				++stats.trianglesCulled;
				continue;
			}
			++stats.trianglesDrawn;
			stats.pixelsWritten += written;
			continue;
		}

		const uint8_t fa = flags_[f[0]], fb = flags_[f[1]], fc = flags_[f[2]];
		if (((fa | fb | fc) & kNotFinite) || (fa & fb & fc & kBehindNear)) {
			++stats.trianglesCulled;
			continue;
		}

		// Crosses the near plane or projects far outside: clip in camera space.
		LazyPlane plane(camera_.data(), f.data(), K);
		ClipVertex poly[kMaxPolygon];
		ClipVertex tmp[kMaxPolygon];
		for (int i = 0; i < 3; ++i)
			poly[i] = {camera_[f[i]].cast<double>(), f[i]};
		int n = clipPolygon(poly, 3, tmp, [nearD](const Eigen::Vector3d &p) { return nearD - p.z(); });
		for (int i = 0; i < n; ++i) {
			poly[i] = tmp[i];
			if (poly[i].index < 0)
				poly[i].p.z() = nearD; // exactly on the plane despite rounding
		}
		bool outside = false;
		for (int i = 0; i < n; ++i) {
			const Eigen::Vector3d &p = poly[i].p;
			outside |= std::abs(K.fx * p.x() / p.z() + K.cx) >= kGuard ||
				   std::abs(K.fy * p.y() / p.z() + K.cy) >= kGuard;
		}
		if (outside) {
			// Guard lines u = +-kGuard/2, v = +-kGuard/2 as planes through the
			// camera centre: fx X + (cx - g) Z <= 0 and so on.
			const double g = kGuard / 2;
			auto clip = [&](auto fn) {
				n = clipPolygon(poly, n, tmp, fn);
				std::copy(tmp, tmp + n, poly);
			};
			clip([&](const Eigen::Vector3d &p) { return K.fx * p.x() + (K.cx - g) * p.z(); });
			clip([&](const Eigen::Vector3d &p) { return -(K.fx * p.x() + (K.cx + g) * p.z()); });
			clip([&](const Eigen::Vector3d &p) { return K.fy * p.y() + (K.cy - g) * p.z(); });
			clip([&](const Eigen::Vector3d &p) { return -(K.fy * p.y() + (K.cy + g) * p.z()); });
		}
		if (n < 3) {
			++stats.trianglesCulled;
			continue;
		}

		Snapped s[kMaxPolygon];
		float zMin = static_cast<float>(poly[0].p.z()), zMax = zMin;
		for (int i = 0; i < n; ++i) {
			const ClipVertex &cv = poly[i];
			if (cv.index >= 0 && screen_[cv.index].sx != kNoScreen)
				s[i] = {screen_[cv.index].sx, screen_[cv.index].sy};
			else
				s[i] = project(cv.p);
			zMin = std::min(zMin, static_cast<float>(cv.p.z()));
			zMax = std::max(zMax, static_cast<float>(cv.p.z()));
		}
		plane.setZRange(zMin, zMax);
		int written = 0;
		bool drawn = false;
		for (int i = 1; i + 1 < n && written >= 0; ++i) {
			if (!tri.setup(s[0], s[i], s[i + 1], target))
				continue;
			drawn = true;
			const int w = tri.scan(plane, target);
			written = w < 0 ? -1 : written + w;
		}
		if (drawn && written >= 0) {
			++stats.trianglesDrawn;
			stats.pixelsWritten += written;
		} else {
			++stats.trianglesCulled;
		}
	}
	return stats;
}

} // namespace ihf
