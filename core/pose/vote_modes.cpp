// SPDX-License-Identifier: MIT
#include "core/pose/vote_modes.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "core/geometry/rotation.h"

namespace ihf {

namespace {

constexpr int kMaxRotationClusters = 128;

// |a - b|^2 summed x, y, z in that order. Eigen's vectorised squaredNorm()
// of a Vector3f adds the squares in another order on SSE than on NEON, so
// a mean shift built on it parts by an ulp between amd64 and aarch64 and
// then converges to other modes (BENCHMARKS.md, Edge targets).
inline float squaredDistance(const Eigen::Vector3f &a, const Eigen::Vector3f &b)
{
	const float dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
	return (dx * dx + dy * dy) + dz * dz;
}
constexpr int kMaxRotationSeeds = 32;

// m += w q q^T (q's coeffs x, y, z, w), element by element: the same bits
// with and without SIMD.
void addOuter(Eigen::Matrix4f &m, float w, const Eigen::Quaternionf &q)
{
	const float c[4] = {q.x(), q.y(), q.z(), q.w()};
	for (int j = 0; j < 4; ++j)
		for (int i = 0; i < 4; ++i)
			m(i, j) += (w * c[i]) * c[j];
}

// Eigenvector of the largest eigenvalue of a symmetric 4x4 matrix, by
// cyclic Jacobi rotations in double, written out in scalar code: Eigen's
// SelfAdjointEigenSolver runs vectorised on SSE and NEON but scalar on
// armhf, and its last bits then differ, so the rotation modes would differ
// between targets. Only +, -, *, / and sqrt (all correctly rounded), in one
// order: the same bits everywhere.
Eigen::Quaternionf principalQuaternion(const Eigen::Matrix4f &m)
{
	double a[4][4], v[4][4];
	double scale = 0;
	for (int i = 0; i < 4; ++i)
		for (int j = 0; j < 4; ++j) {
			a[i][j] = 0.5 * (static_cast<double>(m(i, j)) + static_cast<double>(m(j, i)));
			v[i][j] = i == j ? 1.0 : 0.0;
			scale += a[i][j] * a[i][j];
		}
	for (int sweep = 0; sweep < 16; ++sweep) {
		double off = 0;
		for (int p = 0; p < 4; ++p)
			for (int q = p + 1; q < 4; ++q)
				off += a[p][q] * a[p][q];
		if (!(off > 1e-28 * scale))
			break;
		for (int p = 0; p < 4; ++p)
			for (int q = p + 1; q < 4; ++q) {
				if (a[p][q] == 0.0)
					continue;
				// The rotation in the (p, q) plane that zeroes a[p][q].
				const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
				const double t = std::abs(theta) > 1e150
					? 0.5 / theta
					: (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
				const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
				for (int k = 0; k < 4; ++k) {
					const double akp = a[k][p], akq = a[k][q];
					a[k][p] = c * akp - s * akq;
					a[k][q] = s * akp + c * akq;
				}
				for (int k = 0; k < 4; ++k) {
					const double apk = a[p][k], aqk = a[q][k];
					a[p][k] = c * apk - s * aqk;
					a[q][k] = s * apk + c * aqk;
				}
				for (int k = 0; k < 4; ++k) {
					const double vkp = v[k][p], vkq = v[k][q];
					v[k][p] = c * vkp - s * vkq;
					v[k][q] = s * vkp + c * vkq;
				}
			}
	}
	int best = 0;
	for (int i = 1; i < 4; ++i)
		if (a[i][i] > a[best][best])
			best = i;
	// m's index order is the quaternion's coeffs(): x, y, z, w.
	const double x = v[0][best], y = v[1][best], z = v[2][best], w = v[3][best];
	const double norm = std::sqrt(((x * x + y * y) + z * z) + w * w);
	if (!(norm > 0))
		return Eigen::Quaternionf::Identity();
	return Eigen::Quaternionf(static_cast<float>(w / norm), static_cast<float>(x / norm),
				  static_cast<float>(y / norm), static_cast<float>(z / norm));
}

// Votes binned on a grid of cutoff-sized cells, copied in the order of
// their cell keys into one contiguous array (centre and weight): a
// mean-shift step visits the 27 cells around x instead of every vote, and
// reads them without chasing indices (a step visits most of a box's votes,
// which crowd around the object).
class VoteGrid
{
public:
	// order: scratch for the vote order, then the sorted keys; keys:
	// scratch for one key per vote (floats holding the key's bits: the
	// workspace's scratch, free until the rotation modes); packed: the
	// sorted centres and weights.
	// Every stride-th positive vote is taken, its weight times stride.
	VoteGrid(std::span<const CastVote> votes, std::span<uint32_t> order, std::span<float> keys,
		 std::span<Eigen::Vector4f> packed, float cell, size_t stride)
		: inv_(1.0f / cell)
	{
		origin_ = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
		for (const auto &v : votes)
			if (v.weight > 0)
				origin_ = origin_.cwiseMin(v.centre);
		size_t n = 0;
		const size_t room = std::min(order.size(), packed.size());
		size_t positive = 0;
		for (size_t i = 0; i < votes.size() && n < room; ++i)
			if (votes[i].weight > 0 && positive++ % stride == 0)
				order[n++] = static_cast<uint32_t>(i);
		for (size_t j = 0; j < n; ++j)
			keys[order[j]] = std::bit_cast<float>(key(votes[order[j]].centre));
		const auto keyOf = [&](uint32_t i) { return std::bit_cast<uint32_t>(keys[i]); };
		std::sort(order.begin(), order.begin() + n, [&](uint32_t a, uint32_t b) { return keyOf(a) < keyOf(b); });
		for (size_t j = 0; j < n; ++j) {
			const CastVote &v = votes[order[j]];
			packed[j] = Eigen::Vector4f(v.centre.x(), v.centre.y(), v.centre.z(),
						    stride == 1 ? v.weight : v.weight * static_cast<float>(stride));
			order[j] = keyOf(order[j]); // each slot read before it is written
		}
		keys_ = order.first(n);
		packed_ = packed.first(n);
	}

	// Gaussian-weighted mean of the centres around x; returns the kernel mass.
	// Two phases per row of cells: gather the votes within the cutoff, then
	// weigh them. The same additions in the same order as one loop, but the
	// gather runs without a call to exp in it (twice as fast, measured).
	float meanShiftStep(const Eigen::Vector3f &x, float inv2s2, float cutoff2, Eigen::Vector3f &out) const
	{
		constexpr size_t kBatch = 256;
		uint32_t near[kBatch];
		float nearD2[kBatch];
		float ax = 0, ay = 0, az = 0;
		float mass = 0;
		const Eigen::Vector3i c = cellOf(x);
		const float px = x.x(), py = x.y(), pz = x.z();
		const auto weigh = [&](size_t count) {
			for (size_t i = 0; i < count; ++i) {
				const Eigen::Vector4f &v = packed_[near[i]];
				const float k = v.w() * std::exp(-nearD2[i] * inv2s2);
				ax += k * v.x();
				ay += k * v.y();
				az += k * v.z();
				mass += k;
			}
		};
		for (int dz = -1; dz <= 1; ++dz)
			for (int dy = -1; dy <= 1; ++dy) {
				// The three cells along x are consecutive keys.
				const Eigen::Vector3i lo(c.x() - 1, c.y() + dy, c.z() + dz);
				if (!inRange(lo.y()) || !inRange(lo.z()))
					continue;
				const uint32_t k0 = packed(Eigen::Vector3i(std::max(lo.x(), 0), lo.y(), lo.z()));
				const uint32_t k1 = packed(Eigen::Vector3i(std::min(c.x() + 1, kMaxCell), lo.y(), lo.z()));
				const size_t first = static_cast<size_t>(
					std::lower_bound(keys_.begin(), keys_.end(), k0) - keys_.begin());
				const size_t last = static_cast<size_t>(
					std::upper_bound(keys_.begin() + first, keys_.end(), k1) - keys_.begin());
				size_t count = 0;
				for (size_t j = first; j < last; ++j) {
					const Eigen::Vector4f &v = packed_[j];
					// squaredDistance()'s order of additions.
					const float ex = v.x() - px, ey = v.y() - py, ez = v.z() - pz;
					const float d2 = (ex * ex + ey * ey) + ez * ez;
					near[count] = static_cast<uint32_t>(j);
					nearD2[count] = d2;
					count += d2 <= cutoff2;
					if (count == kBatch) {
						weigh(count);
						count = 0;
					}
				}
				weigh(count);
			}
		out = mass > 0 ? Eigen::Vector3f(Eigen::Vector3f(ax, ay, az) / mass) : x;
		return mass;
	}

private:
	static constexpr int kMaxCell = 1023; // 10 bits per axis
	static bool inRange(int i) { return i >= 0 && i <= kMaxCell; }
	Eigen::Vector3i cellOf(const Eigen::Vector3f &p) const
	{
		const Eigen::Vector3f f = ((p - origin_) * inv_).array().floor().max(-1.0f).min(kMaxCell + 1.0f);
		return f.cast<int>();
	}
	static uint32_t packed(const Eigen::Vector3i &c)
	{
		return static_cast<uint32_t>(c.z()) << 20 | static_cast<uint32_t>(c.y()) << 10 |
		       static_cast<uint32_t>(c.x());
	}
	uint32_t key(const Eigen::Vector3f &p) const
	{
		return packed(cellOf(p).cwiseMax(0).cwiseMin(kMaxCell));
	}

	std::span<uint32_t> keys_;        // sorted
	std::span<Eigen::Vector4f> packed_; // x, y, z, weight in key order
	Eigen::Vector3f origin_;
	float inv_;
};

} // namespace

Eigen::Quaternionf averageQuaternion(std::span<const Eigen::Quaternionf> qs,
				    std::span<const float> weights)
{
	Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
	for (size_t i = 0; i < qs.size(); ++i) {
		float w = weights.empty() ? 1.0f : weights[i];
		addOuter(m, w, qs[i]);
	}
	return principalQuaternion(m);
}

namespace {

// Translation mean shift steps of one seed are at most this many (the
// config's maxIterations is clamped), so a seed's whole path fits a trail.
constexpr int kMaxTrail = 64;
constexpr size_t kMaxBatch = WorkerPool::kMaxThreads;
// Translation modes whose rotations run on several threads (more: one).
constexpr size_t kMaxCentres = 64;

// The path of one seed's mean shift: x[0] the seed, x[j] after j steps.
struct SeedTrail {
	std::array<Eigen::Vector3f, kMaxTrail + 1> x;
	int steps = 0;
	bool done = false;    // the last step moved less than the tolerance
	bool stopped = false; // its end is near a mode found before it
	float mass = 0;       // kernel mass at its end, if not stopped
};

// A converged seed: merged into a mode it meets (which keeps the denser
// centre), else a new mode, else it replaces the weakest if denser.
void addTranslationMode(std::span<PoseMode> modes, size_t &found, size_t cap, float merge2,
			const Eigen::Vector3f &x, float mass)
{
	for (size_t m = 0; m < found; ++m) {
		if (squaredDistance(modes[m].centre, x) < merge2) {
			if (mass > modes[m].translationDensity) {
				modes[m].centre = x;
				modes[m].translationDensity = mass;
			}
			return;
		}
	}
	if (found < cap) {
		modes[found++] = PoseMode{x, Eigen::Quaternionf::Identity(), mass, 0, 0};
		return;
	}
	auto weakest = std::min_element(modes.begin(), modes.begin() + found, [](const PoseMode &a, const PoseMode &b) {
		return a.translationDensity < b.translationDensity;
	});
	if (mass > weakest->translationDensity)
		*weakest = PoseMode{x, Eigen::Quaternionf::Identity(), mass, 0, 0};
}

} // namespace

size_t findPoseModes(std::span<const CastVote> votes, const VoteModeConfig &config,
		     VoteModeWorkspace ws, std::span<PoseMode> modes)
{
	if (votes.empty() || modes.empty())
		return 0;
	const float h = config.translationBandwidth;
	const float inv2s2 = 1.0f / (2.0f * h * h);
	const float cutoff = 3.0f * h;
	const float cutoff2 = cutoff * cutoff;
	const float support2 = config.supportRadius * h * config.supportRadius * h;

	// Seeds: positive-weight votes at an even stride over the list.
	size_t positive = 0;
	for (const auto &v : votes)
		positive += v.weight > 0;
	if (positive == 0)
		return 0;
	const size_t seedCount = std::min({positive, ws.seeds.size(),
					   static_cast<size_t>(std::max(1, config.maxSeeds))});
	const size_t stride = std::max<size_t>(1, positive / seedCount);
	size_t s = 0, k = 0;
	for (const auto &v : votes) {
		if (v.weight <= 0)
			continue;
		if (k++ % stride == 0 && s < seedCount)
			ws.seeds[s++] = v.centre;
	}

	// Mean-shift each seed to its mode; merge modes that meet. Room is left
	// for rotationModesPerCentre modes per translation mode.
	const int perCentre = static_cast<int>(
		std::min<size_t>(std::max(1, config.rotationModesPerCentre), modes.size()));
	const size_t centreCap = modes.size() / perCentre;
	size_t found = 0;
	const float merge2 = config.mergeDistance * h * config.mergeDistance * h;
	const size_t shiftStride =
		config.maxShiftVotes > 0
			? (positive + static_cast<size_t>(config.maxShiftVotes) - 1) / static_cast<size_t>(config.maxShiftVotes)
			: 1;
	const VoteGrid grid(votes, ws.support, ws.scratch, ws.packed, cutoff, std::max<size_t>(1, shiftStride));
	const float tolerance = 1e-4f * h * h;
	const int maxIterations = std::min(config.maxIterations, kMaxTrail);
	// A seed that reaches a mode already found climbs no further.
	const auto nearFound = [&](const Eigen::Vector3f &p) {
		for (size_t m = 0; m < found; ++m)
			if (squaredDistance(modes[m].centre, p) < merge2)
				return true;
		return false;
	};
	// Climbs tr from its step `from` until it stops moving, meets a mode
	// found, or runs out of steps; the kernel mass at its end if no mode.
	const auto climb = [&](SeedTrail &tr, int from) {
		int j = from;
		tr.done = tr.stopped = false;
		while (j < maxIterations) {
			Eigen::Vector3f next;
			grid.meanShiftStep(tr.x[j], inv2s2, cutoff2, next);
			tr.done = squaredDistance(next, tr.x[j]) < tolerance;
			tr.x[++j] = next;
			if (nearFound(next)) {
				tr.stopped = true;
				break;
			}
			if (tr.done)
				break;
		}
		tr.steps = j;
		if (!tr.stopped) {
			Eigen::Vector3f unused;
			tr.mass = grid.meanShiftStep(tr.x[j], inv2s2, cutoff2, unused);
		}
	};
	// Seeds climb in batches, one per thread, against the modes found before
	// the batch; then, in seed order, each trail is checked against the modes
	// found so far, which may stop it earlier, as one seed after the other
	// would have. A trail stopped by a mode that has since been replaced
	// (the weakest, when the modes are full) climbs on.
	// The modes are those of one thread, for any number of threads.
	const int batch = ws.pool ? std::min(ws.pool->threads(), static_cast<int>(kMaxBatch)) : 1;
	std::array<SeedTrail, kMaxBatch> trails;
	for (size_t i0 = 0; i0 < s; i0 += static_cast<size_t>(batch)) {
		const int nb = static_cast<int>(std::min(s - i0, static_cast<size_t>(batch)));
		const auto task = [&](int b, int) {
			SeedTrail &tr = trails[static_cast<size_t>(b)];
			tr.x[0] = ws.seeds[i0 + static_cast<size_t>(b)];
			climb(tr, 0);
		};
		if (nb > 1)
			ws.pool->run(nb, task);
		else
			task(0, 0);
		for (int b = 0; b < nb; ++b) {
			SeedTrail &tr = trails[static_cast<size_t>(b)];
			bool reached = false;
			for (int j = 1; j <= tr.steps && !reached; ++j)
				reached = nearFound(tr.x[j]);
			if (reached)
				continue;
			if (tr.stopped) {
				if (!tr.done)
					climb(tr, tr.steps);
				else {
					Eigen::Vector3f unused;
					tr.stopped = false;
					tr.mass = grid.meanShiftStep(tr.x[tr.steps], inv2s2, cutoff2, unused);
				}
				if (tr.stopped)
					continue;
			}
			addTranslationMode(modes, found, centreCap, merge2, tr.x[tr.steps], tr.mass);
		}
	}
	std::sort(modes.begin(), modes.begin() + found, [](const PoseMode &a, const PoseMode &b) {
		return a.translationDensity > b.translationDensity;
	});

	// Rotation modes among each translation mode's supporting votes, each
	// mode on its own (spread over the threads, each with its own scratch)
	// from a copy of the translation modes, into its slots m*R...
	const float rs = config.rotationBandwidth;
	const float invR = 1.0f / (2.0f * rs * rs);
	const float cosCluster = std::cos(0.5f * rs); // quaternion dot at angle rs
	const float cosCutoff = std::cos(std::min(1.5f * rs, 0.5f * static_cast<float>(M_PI)));
	const int threads = ws.pool && ws.support.size() >= votes.size() && ws.threadScratch.size() >= (ws.pool->threads() - 1) * votes.size() &&
				    ws.threadSupport.size() >= (ws.pool->threads() - 1) * votes.size() && found <= kMaxCentres
			    ? ws.pool->threads()
			    : 1;
	std::array<PoseMode, kMaxCentres> centres;
	const auto rotationModes = [&](size_t mm, int thread) {
		const PoseMode centre = threads > 1 ? centres[mm] : modes[mm];
		std::span<float> w = thread == 0 ? ws.scratch.first(votes.size())
						 : ws.threadScratch.subspan((thread - 1) * votes.size(), votes.size());
		std::span<uint32_t> sup =
			thread == 0 ? ws.support.first(std::min(ws.support.size(), votes.size()))
				    : ws.threadSupport.subspan((thread - 1) * votes.size(), votes.size());
		float support = 0;
		size_t ns = 0;
		for (size_t i = 0; i < votes.size(); ++i) {
			float d2 = squaredDistance(votes[i].centre, centre.centre);
			bool in = votes[i].weight > 0 && d2 <= support2;
			w[i] = in ? votes[i].weight * std::exp(-d2 * inv2s2) : 0.0f;
			support += in ? votes[i].weight : 0.0f;
			if (in && ns < sup.size())
				sup[ns++] = static_cast<uint32_t>(i);
		}
		// Seeds: a greedy clustering of the supporting rotations, heaviest
		// vote first, one cluster per rotation bandwidth; the heaviest
		// clusters seed the mean shift. Weak but distinct rotations thus
		// get seeds even when one cluster holds most votes.
		std::sort(sup.begin(), sup.begin() + ns, [&](uint32_t a, uint32_t b) { return w[a] > w[b]; });
		Eigen::Quaternionf clusterQ[kMaxRotationClusters];
		float clusterW[kMaxRotationClusters];
		int nClusters = 0;
		for (size_t k = 0; k < ns; ++k) {
			const Eigen::Quaternionf &q = votes[sup[k]].rotation;
			int c = 0;
			while (c < nClusters && quatSimilarity(q, clusterQ[c]) < cosCluster)
				++c;
			if (c < nClusters) {
				clusterW[c] += w[sup[k]];
			} else if (nClusters < kMaxRotationClusters) {
				clusterQ[nClusters] = q;
				clusterW[nClusters++] = w[sup[k]];
			}
		}
		int clusterOrder[kMaxRotationClusters];
		for (int j = 0; j < nClusters; ++j)
			clusterOrder[j] = j;
		std::sort(clusterOrder, clusterOrder + nClusters,
			  [&](int a, int b) { return clusterW[a] > clusterW[b]; });
		const int nSeeds = std::min({nClusters, kMaxRotationSeeds, std::max(8, 2 * perCentre)});
		Eigen::Quaternionf found_q[kMaxRotationSeeds];
		float found_d[kMaxRotationSeeds];
		int nFound = 0;
		for (int sIdx = 0; sIdx < nSeeds; ++sIdx) {
			Eigen::Quaternionf q = clusterQ[clusterOrder[sIdx]];
			float density = 0;
			for (int it = 0; it < config.maxIterations; ++it) {
				Eigen::Matrix4f acc = Eigen::Matrix4f::Zero();
				density = 0;
				for (size_t k = 0; k < ns; ++k) {
					const CastVote &v = votes[sup[k]];
					// Beyond three bandwidths the kernel is < 1.2e-2.
					if (quatSimilarity(q, v.rotation) < cosCutoff)
						continue;
					float a = quatAngle(q, v.rotation);
					float kk = w[sup[k]] * std::exp(-a * a * invR);
					density += kk;
					addOuter(acc, kk, v.rotation);
				}
				Eigen::Quaternionf nq = principalQuaternion(acc);
				bool done = quatAngle(nq, q) < 1e-3f;
				q = nq;
				if (done)
					break;
			}
			// Seeds converging to the same rotation are one mode.
			int same = -1;
			for (int j = 0; j < nFound && same < 0; ++j)
				if (quatAngle(found_q[j], q) < rs)
					same = j;
			if (same < 0) {
				found_q[nFound] = q;
				found_d[nFound++] = density;
			} else if (density > found_d[same]) {
				found_q[same] = q;
				found_d[same] = density;
			}
		}
		// Densest first.
		int order[kMaxRotationSeeds];
		for (int j = 0; j < nFound; ++j)
			order[j] = j;
		for (int j = 1; j < nFound; ++j) // insertion sort: at most kMaxRotationSeeds
			for (int i = j; i > 0 && found_d[order[i]] > found_d[order[i - 1]]; --i)
				std::swap(order[i], order[i - 1]);
		const int keep = std::max(1, std::min(perCentre, nFound));
		for (int j = 0; j < keep; ++j) {
			PoseMode &out = modes[mm * perCentre + j];
			out = centre;
			out.supportWeight = support;
			out.rotation = nFound ? found_q[order[j]] : Eigen::Quaternionf::Identity();
			out.rotationDensity = nFound ? found_d[order[j]] : 0.0f;
		}
		for (int j = keep; j < perCentre; ++j)
			modes[mm * perCentre + j].supportWeight = -1; // empty slot
	};
	if (threads > 1) {
		std::copy(modes.begin(), modes.begin() + found, centres.begin());
		ws.pool->run(static_cast<int>(found), [&](int mm, int thread) { rotationModes(static_cast<size_t>(mm), thread); });
	} else {
		// ...written from the last mode back so a mode's slots never
		// overwrite one not yet processed (slot m*R >= m).
		for (size_t mm = found; mm-- > 0;)
			rotationModes(mm, 0);
	}
	const size_t written = found * static_cast<size_t>(perCentre);
	// Close the gaps left by centres with fewer rotation modes.
	size_t count = 0;
	for (size_t i = 0; i < written; ++i)
		if (modes[i].supportWeight >= 0)
			modes[count++] = modes[i];
	return count;
}

} // namespace ihf
