// SPDX-License-Identifier: MIT
#include "core/synth/sequence_config.h"

#include <string>

namespace ihf {

Status validateSequenceConfig(const SequenceConfig &c)
{
	const SequenceParams &p = c.params;
	const LayoutParams &l = p.synth.layout;
	auto bad = [](const std::string &m) { return Status(makeError(Errc::kInvalidArgument, m)); };
	if (c.modelsDir.empty())
		return bad("--models: no models folder given");
	if (c.outDir.empty())
		return bad("--out: no output folder given");
	if (c.objects.empty())
		return bad("--objects: no object id given");
	if (c.sequences < 1 || c.sequences > 10000)
		return bad("--sequences " + std::to_string(c.sequences) + ": must be 1..10000");
	if (p.frames < 1 || p.frames > 100000)
		return bad("--frames " + std::to_string(p.frames) + ": must be 1..100000");
	if (p.perFrameMin < 1 || p.perFrameMax > 16 || p.perFrameMin > p.perFrameMax)
		return bad("--per-frame: must lie within 1:16 with MIN <= MAX");
	if (p.perFrameMax > static_cast<int>(c.objects.size()))
		return bad("--per-frame " + std::to_string(p.perFrameMin) + ":" +
			   std::to_string(p.perFrameMax) + ": needs at least " +
			   std::to_string(p.perFrameMax) + " ids in --objects (got " +
			   std::to_string(c.objects.size()) + ")");
	if (p.motion != CameraMotion::kHandheld && p.motion != CameraMotion::kRobot &&
	    p.motion != CameraMotion::kMixed)
		return bad("--motion: expected handheld, robot or mixed");
	if (p.path.distanceMin < 450 || p.path.distanceMax > 3500 ||
	    p.path.distanceMin > p.path.distanceMax)
		return bad("--distance: must lie within 450:3500 mm with MIN <= MAX");
	if (p.path.elevationMinDeg < 5 || p.path.elevationMaxDeg > 85 ||
	    p.path.elevationMinDeg > p.path.elevationMaxDeg)
		return bad("--elevation: must lie within 5:85 degrees with MIN <= MAX");
	if (!(p.path.maxSpeedMmS >= 100 && p.path.maxSpeedMmS <= 3000))
		return bad("--max-speed: must lie within 0.1..3 m/s");
	if (!(p.path.maxTurnDegS >= 20 && p.path.maxTurnDegS <= 720))
		return bad("--max-turn: must lie within 20..720 deg/s");
	if (!(p.detector.missProbability >= 0 && p.detector.missProbability <= 1))
		return bad("--miss: probability must be in [0, 1]");
	if (!(p.changeProbability >= 0 && p.changeProbability <= 1))
		return bad("--change: probability must be in [0, 1]");
	if (l.clutterMin < 0 || l.clutterMax > 30 || l.clutterMin > l.clutterMax)
		return bad("--clutter: must lie within 0:30 with MIN <= MAX");
	if (l.wallProbability < 0 || l.wallProbability > 1)
		return bad("--wall: probability must be in [0, 1]");
	if (!(p.synth.depthScale == 1.0 || p.synth.depthScale == 0.1))
		return bad("--depth-scale: must be 1 (mm) or 0.1 (0.1 mm)");
	std::error_code ec;
	const auto outAbs = std::filesystem::weakly_canonical(c.outDir, ec);
	const auto modelsAbs = std::filesystem::weakly_canonical(c.modelsDir, ec);
	if (!ec && outAbs == modelsAbs)
		return bad("--out: must differ from --models");
	return {};
}

} // namespace ihf
