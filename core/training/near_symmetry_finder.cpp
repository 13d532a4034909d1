// SPDX-License-Identifier: MIT
#include "core/training/near_symmetry_finder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <unordered_map>

#include <Eigen/Dense>

#include "core/training/turn_views.h"

namespace ihf {

namespace {

struct Sample {
	Eigen::Vector3d p;
	Eigen::Vector3d n;
};

// A deterministic uniform in [0, 1) (splitmix64), the same on every target.
class SampleSequence
{
public:
	double next()
	{
		uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
		z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
		z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
		z ^= z >> 31;
		return static_cast<double>(z >> 11) * 0x1.0p-53;
	}

private:
	uint64_t state_ = 0x1234567;
};

std::vector<Sample> sampleSurface(const Mesh &mesh, int count)
{
	std::vector<double> cumulative;
	cumulative.reserve(mesh.faces.size());
	double total = 0;
	for (const auto &f : mesh.faces) {
		const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>(), b = mesh.vertices[f[1]].cast<double>(),
				      c = mesh.vertices[f[2]].cast<double>();
		total += 0.5 * (b - a).cross(c - a).norm();
		cumulative.push_back(total);
	}
	std::vector<Sample> out;
	if (total <= 0)
		return out;
	SampleSequence rng;
	out.reserve(static_cast<size_t>(count));
	for (int i = 0; i < count; ++i) {
		const double r = rng.next() * total;
		const size_t fi = std::min(static_cast<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), r) -
							       cumulative.begin()),
					   mesh.faces.size() - 1);
		const auto &f = mesh.faces[fi];
		const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>(), b = mesh.vertices[f[1]].cast<double>(),
				      c = mesh.vertices[f[2]].cast<double>();
		double u = rng.next(), v = rng.next();
		if (u + v > 1) {
			u = 1 - u;
			v = 1 - v;
		}
		const Eigen::Vector3d n = (b - a).cross(c - a);
		if (n.norm() <= 0)
			continue;
		out.push_back({a + u * (b - a) + v * (c - a), n.normalized()});
	}
	return out;
}

// Samples binned on a grid of cell `cell`; nearest() looks at the 27 cells
// round a point.
class SampleGrid
{
public:
	SampleGrid(const std::vector<Sample> &samples, double cell) : samples_(samples), cell_(cell)
	{
		for (size_t i = 0; i < samples.size(); ++i)
			cells_[key(index(samples[i].p))].push_back(static_cast<uint32_t>(i));
	}

	// The sample nearest p within the cell size whose normal agrees with n
	// (cos > 0.5), or null.
	const Sample *nearest(const Eigen::Vector3d &p, const Eigen::Vector3d &n) const
	{
		const Sample *best = nullptr;
		double bestD = cell_ * cell_;
		const Eigen::Vector3i c = index(p);
		for (int dz = -1; dz <= 1; ++dz)
			for (int dy = -1; dy <= 1; ++dy)
				for (int dx = -1; dx <= 1; ++dx) {
					auto it = cells_.find(key(Eigen::Vector3i(c + Eigen::Vector3i(dx, dy, dz))));
					if (it == cells_.end())
						continue;
					for (uint32_t i : it->second) {
						const Sample &s = samples_[i];
						const double d = (s.p - p).squaredNorm();
						if (d < bestD && s.n.dot(n) > 0.5) {
							bestD = d;
							best = &s;
						}
					}
				}
		return best;
	}

private:
	Eigen::Vector3i index(const Eigen::Vector3d &p) const
	{
		return (p / cell_).array().floor().cast<int>().matrix();
	}
	static int64_t key(const Eigen::Vector3i &c)
	{
		return (static_cast<int64_t>(c.x()) & 0x1fffff) | (static_cast<int64_t>(c.y()) & 0x1fffff) << 21 |
		       (static_cast<int64_t>(c.z()) & 0x1fffff) << 42;
	}

	const std::vector<Sample> &samples_;
	double cell_;
	std::unordered_map<int64_t, std::vector<uint32_t>> cells_;
};

Eigen::Matrix3d turnAbout(const Eigen::Vector3d &axis, double deg)
{
	return Eigen::AngleAxisd(deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
}

// Moves the axis' point so that the turns fit the surface best: each turned
// sample matched to a surface sample, the point-to-plane residuals
// n . (R (p - c) + c - q) minimised over c (its component along the axis
// held).
Eigen::Vector3d fitAxisPoint(const std::vector<Sample> &samples, const SampleGrid &grid, const Eigen::Vector3d &axis,
			     Eigen::Vector3d point, double deg)
{
	const Eigen::Matrix3d R = turnAbout(axis, deg);
	const Eigen::Matrix3d IR = Eigen::Matrix3d::Identity() - R;
	for (int iter = 0; iter < 6; ++iter) {
		Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
		Eigen::Vector3d b = Eigen::Vector3d::Zero();
		int matched = 0;
		for (const Sample &s : samples) {
			const Eigen::Vector3d p = R * (s.p - point) + point;
			const Sample *q = grid.nearest(p, R * s.n);
			if (!q)
				continue;
			// n . (R p + (I - R) c - q) = 0 in c.
			const Eigen::Vector3d v = IR.transpose() * q->n;
			A += v * v.transpose();
			b += v * q->n.dot(q->p - R * s.p);
			++matched;
		}
		if (matched < 10)
			break;
		const double lambda = A.trace() + 1.0;
		A += lambda * axis * axis.transpose();
		b += lambda * axis * axis.dot(point);
		const Eigen::Vector3d next = A.ldlt().solve(b);
		if (!next.allFinite())
			break;
		const double moved = (next - point).norm();
		point = next;
		if (moved < 1e-3)
			break;
	}
	return point;
}

// Share of the samples the turn moves off the surface, or a share of at
// least giveUpAt once that is certain (the rest is not looked at).
double differingShare(const std::vector<Sample> &samples, const SampleGrid &grid, const Eigen::Vector3d &axis,
		      const Eigen::Vector3d &point, double deg, double matchMm, double giveUpAt)
{
	if (samples.empty())
		return 1.0;
	const Eigen::Matrix3d R = turnAbout(axis, deg);
	const double n = static_cast<double>(samples.size());
	size_t off = 0;
	for (const Sample &s : samples) {
		const Eigen::Vector3d p = R * (s.p - point) + point;
		const Sample *q = grid.nearest(p, R * s.n);
		if (!q || std::abs(q->n.dot(p - q->p)) > matchMm)
			if (static_cast<double>(++off) / n >= giveUpAt)
				break;
	}
	return static_cast<double>(off) / n;
}

struct CandidateAxis {
	Eigen::Vector3d axis;
	Eigen::Vector3d point;
};

std::vector<CandidateAxis> candidateAxes(const Mesh &mesh, const std::vector<Sample> &samples)
{
	std::vector<CandidateAxis> out;
	Eigen::Vector3d mean = Eigen::Vector3d::Zero();
	for (const Sample &s : samples)
		mean += s.p;
	mean /= static_cast<double>(samples.size());
	Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
	for (const Sample &s : samples)
		cov += (s.p - mean) * (s.p - mean).transpose();
	const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
	const Eigen::Vector3d boxCentre = boundingBox(mesh).centre().cast<double>();
	for (int i = 0; i < 3; ++i)
		out.push_back({Eigen::Vector3d::Unit(i), boxCentre});
	for (int i = 0; i < 3; ++i) {
		Eigen::Vector3d a = eig.eigenvectors().col(i).normalized();
		// One sign, so that the same axis is not tried twice.
		if (a.cwiseAbs().maxCoeff() == std::abs(a.minCoeff()))
			a = -a;
		bool same = false;
		for (const CandidateAxis &c : out)
			same = same || std::abs(c.axis.dot(a)) > std::cos(10.0 * std::numbers::pi / 180.0);
		if (!same)
			out.push_back({a, mean});
	}
	return out;
}

} // namespace

std::vector<NearSymmetry> findNearSymmetries(const Mesh &mesh, const NearSymmetryConfig &config)
{
	std::vector<NearSymmetry> found;
	if (mesh.faces.empty() || config.stepDeg <= 0 || config.stepDeg >= 180)
		return found;
	const std::vector<Sample> samples = sampleSurface(mesh, config.samples);
	if (samples.size() < 100)
		return found;
	const double diameter = meshDiameter(mesh);
	const double matchMm = config.matchShare * diameter;
	const SampleGrid fine(samples, 2.0 * matchMm);
	TurnViews views(mesh, config.views);
	const int steps = static_cast<int>(std::lround(360.0 / config.stepDeg));
	const double step = 360.0 / steps;

	for (const CandidateAxis &c : candidateAxes(mesh, samples)) {
		// The axis placed where its half-turn moves the least surface off
		// the surface: a search over points of the plane square to it round
		// the box centre (a part can pull the box centre tens of millimetres
		// off the axis; a least-squares fit from there locks onto the part),
		// then a point-to-plane fit from the best.
		const Eigen::Vector3d u = c.axis.unitOrthogonal(), w = c.axis.cross(u);
		const double reach = 0.25 * diameter, stepMm = 2.0 * matchMm;
		const int n = static_cast<int>(std::ceil(reach / stepMm));
		Eigen::Vector3d point = c.point;
		double bestShare = 2.0;
		for (int i = -n; i <= n; ++i)
			for (int j = -n; j <= n; ++j) {
				const Eigen::Vector3d p = c.point + (i * stepMm) * u + (j * stepMm) * w;
				const double share = differingShare(samples, fine, c.axis, p, 180.0, matchMm, bestShare);
				if (share < bestShare) {
					bestShare = share;
					point = p;
				}
			}
		point = fitAxisPoint(samples, fine, c.axis, point, 180.0);
		// Held where it crosses the plane through the box centre square to
		// the axis, so the same axis is stored the same way.
		point -= c.axis * c.axis.dot(point - c.point);
		// Each turn as the estimator would see it (turn_views.h).
		std::vector<TurnLook> looks;
		for (int k = 1; k < steps; ++k)
			looks.push_back(views.compare(c.axis, point, k * step, config.maxShare));
		double worst = 0;
		for (const TurnLook &l : looks)
			worst = std::max(worst, l.meanShare);
		auto add = [&](double deg, const TurnLook &look) {
			for (const NearSymmetry &s : found)
				if (std::abs(s.axis.cast<double>().dot(c.axis)) > std::cos(10.0 * std::numbers::pi / 180.0) &&
				    (s.continuous() || std::abs(s.turnDeg - deg) < 1e-3 ||
				     std::abs(s.turnDeg - (360.0 - deg)) < 1e-3))
					return;
			NearSymmetry s;
			s.axis = c.axis.cast<float>();
			s.point = point.cast<float>();
			s.turnDeg = static_cast<float>(deg);
			s.differingShare = static_cast<float>(look.meanShare);
			s.alikeViews = static_cast<float>(look.alikeViews);
			found.push_back(s);
		};
		if (worst <= config.maxShare) {
			TurnLook all;
			all.meanShare = worst;
			all.alikeViews = 1;
			for (const TurnLook &l : looks)
				all.alikeViews = std::min(all.alikeViews, l.alikeViews);
			add(0.0, all);
			continue;
		}
		// A turn and its reverse are one near-symmetry (the rival of a pose
		// is tried both ways round).
		for (int k = 1; 2 * k <= steps; ++k) {
			const TurnLook &there = looks[static_cast<size_t>(k - 1)], &back = looks[static_cast<size_t>(steps - k - 1)];
			TurnLook both;
			both.meanShare = std::max(there.meanShare, back.meanShare);
			both.alikeViews = std::min(there.alikeViews, back.alikeViews);
			if (both.meanShare <= config.maxShare)
				add(k * step, both);
		}
	}
	std::stable_sort(found.begin(), found.end(), [](const NearSymmetry &a, const NearSymmetry &b) {
		return a.differingShare < b.differingShare;
	});
	if (found.size() > static_cast<size_t>(std::max(config.maxFound, 0)))
		found.resize(static_cast<size_t>(std::max(config.maxFound, 0)));
	return found;
}

std::string describeNearSymmetry(const NearSymmetry &s)
{
	char turn[32];
	if (s.continuous())
		std::snprintf(turn, sizeof(turn), "any turn");
	else
		std::snprintf(turn, sizeof(turn), "a turn by %.0f deg", static_cast<double>(s.turnDeg));
	char line[256];
	std::snprintf(line, sizeof(line), "%s about (%.3f, %.3f, %.3f) through (%.1f, %.1f, %.1f) mm: %.1f %% of the pixels differ",
		      turn, static_cast<double>(s.axis.x()), static_cast<double>(s.axis.y()), static_cast<double>(s.axis.z()),
		      static_cast<double>(s.point.x()), static_cast<double>(s.point.y()), static_cast<double>(s.point.z()),
		      100.0 * static_cast<double>(s.differingShare));
	std::string out = line;
	if (s.alikeViews >= 0) {
		std::snprintf(line, sizeof(line), ", alike in %.0f %% of the views", 100.0 * static_cast<double>(s.alikeViews));
		out += line;
	}
	return out;
}

} // namespace ihf
