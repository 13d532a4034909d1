// SPDX-License-Identifier: MIT
#include "core/eval/visible_surface.h"

#include <cmath>

namespace ihf {

namespace {

std::vector<double> fiveHundredths()
{
	std::vector<double> v;
	for (int i = 1; i <= 10; ++i)
		v.push_back(i * 0.05);
	return v;
}

// Distance from the camera centre of the point at depth z seen in pixel
// (x, y), over z.
class RayLength
{
public:
	explicit RayLength(const CameraIntrinsics &K) : K_(K) {}
	double operator()(int x, int y) const
	{
		const double u = (x - K_.cx) / K_.fx, v = (y - K_.cy) / K_.fy;
		return std::sqrt(1.0 + u * u + v * v);
	}

private:
	CameraIntrinsics K_;
};

// BOP's "bop19" visibility: drawn, and not behind the test surface by more
// than delta (or the test has no depth there). Distances along the ray.
bool visible(float model, float test, double ray)
{
	return model > 0 && (test <= 0 || (model - test) * ray <= kVsdDeltaMm);
}

} // namespace

std::vector<double> vsdTauShares()
{
	return fiveHundredths();
}

std::vector<double> vsdThetas()
{
	return fiveHundredths();
}

VisibleSurfaceScorer::VisibleSurfaceScorer(const Mesh &mesh) : mesh_(mesh)
{
	renderer_.reserve(mesh.vertices.size());
}

Expected<std::vector<double>> VisibleSurfaceScorer::errors(const Pose &est, const Pose &gt,
							    ImageView<const float> testDepth,
							    const CameraIntrinsics &K,
							    std::span<const double> tausMm)
{
	if (!(K.fx > 0 && K.fy > 0) || testDepth.empty())
		return makeError(Errc::kInvalidArgument, "visible surface discrepancy: no camera or no depth image");
	const int w = testDepth.width, h = testDepth.height;
	DepthImageMm estDepth(w, h, 0.0f), gtDepth(w, h, 0.0f);
	CameraIntrinsics k = K;
	k.width = w;
	k.height = h;
	for (auto [pose, image] : {std::pair{&est, &estDepth}, std::pair{&gt, &gtDepth}}) {
		Expected<RenderStats> drawn = renderer_.render(mesh_, *pose, k, image->view());
		if (!drawn)
			return drawn.error();
	}

	// Union of the visible masks, pixels in one only, and the distance
	// differences on the pixels in both.
	const RayLength rayLength(k);
	size_t unionCount = 0, oneOnly = 0;
	std::vector<double> differences;
	for (int y = 0; y < h; ++y) {
		for (int x = 0; x < w; ++x) {
			const float e = estDepth.at(x, y), g = gtDepth.at(x, y);
			if (e <= 0 && g <= 0)
				continue;
			const float test = testDepth.at(x, y);
			const double ray = rayLength(x, y);
			const bool gtVisible = visible(g, test, ray);
			const bool estVisible = visible(e, test, ray) || (gtVisible && e > 0);
			if (!gtVisible && !estVisible)
				continue;
			++unionCount;
			if (gtVisible && estVisible)
				differences.push_back(std::abs(static_cast<double>(e) - g) * ray);
			else
				++oneOnly;
		}
	}

	std::vector<double> result;
	for (double tau : tausMm) {
		if (unionCount == 0) {
			result.push_back(1.0);
			continue;
		}
		size_t cost = oneOnly;
		for (double d : differences)
			cost += d >= tau;
		result.push_back(static_cast<double>(cost) / static_cast<double>(unionCount));
	}
	return result;
}

} // namespace ihf
