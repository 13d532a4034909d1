// SPDX-License-Identifier: MIT
// `ihf synth`: realistic synthetic depth test scenes in BOP layout.

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/synth/synth_dataset.h"
#include "firmware_app/command.h"

namespace ihf::app {

namespace {

struct SynthOptions {
	std::string models;
	std::string objects;
	int images = 50;
	uint64_t seed = 0;
	std::string out;
	std::string distance = "700:800";
	std::string occlusion = "0:0.6";
	std::string elevation = "15:75";
	std::string clutter = "4:10";
	double wall = 0.4;
	std::string camera;
	std::string sensor = "kinect";
	double depthScale = 1.0;
	std::string preview;
	int previewCount = 4;
	bool overwrite = false;
	bool quiet = false;
};

int usage(const std::string &message)
{
	std::fprintf(stderr, "ihf synth: %s\n", message.c_str());
	return kExitUsage;
}

void printSummary(const SynthSummary &s)
{
	if (s.occlusion.empty())
		return;
	double sum = 0, lo = 1, hi = 0;
	int bins[10] = {};
	for (double o : s.occlusion) {
		sum += o;
		lo = std::min(lo, o);
		hi = std::max(hi, o);
		++bins[std::clamp(static_cast<int>(o * 10.0), 0, 9)];
	}
	std::fprintf(stderr, "synth: %d images in %.1f s (%.2f s/image), %d attempts, %d occluders, %d cut by the border\n",
		     s.images, s.seconds, s.seconds / std::max(s.images, 1), s.attemptsTotal,
		     s.occludersTotal, s.truncated);
	std::fprintf(stderr, "synth: occlusion (1 - visib_fract) mean %.3f min %.3f max %.3f\n",
		     sum / s.occlusion.size(), lo, hi);
	for (int b = 0; b < 10; ++b)
		if (bins[b])
			std::fprintf(stderr, "synth:   [%.1f, %.1f) %5d\n", b / 10.0, (b + 1) / 10.0, bins[b]);
}

int runSynthCommand(const SynthOptions &o)
{
	SynthConfig c;
	c.modelsDir = o.models;
	c.outDir = o.out;
	c.cameraFile = o.camera;
	c.images = o.images;
	c.previewDir = o.preview;
	c.previewCount = o.previewCount;
	c.overwrite = o.overwrite;
	c.params.seed = o.seed;
	c.params.depthScale = o.depthScale;
	c.params.layout.wallProbability = o.wall;
	const std::optional<SensorModel> model = sensorModelNamed(o.sensor);
	if (!model)
		return usage("--sensor '" + o.sensor + "': expected kinect, tof or ideal");
	c.params.model = *model;

	auto ids = parseIdList(o.objects, "--objects");
	if (!ids)
		return usage(ids.error().message);
	c.objects = *ids;
	auto distance = parseRange(o.distance, "--distance");
	if (!distance)
		return usage(distance.error().message);
	c.params.layout.distanceMin = distance->first;
	c.params.layout.distanceMax = distance->second;
	auto occlusion = parseRange(o.occlusion, "--occlusion");
	if (!occlusion)
		return usage(occlusion.error().message);
	c.params.occlusionMin = occlusion->first;
	c.params.occlusionMax = occlusion->second;
	auto elevation = parseRange(o.elevation, "--elevation");
	if (!elevation)
		return usage(elevation.error().message);
	c.params.layout.elevationMinDeg = elevation->first;
	c.params.layout.elevationMaxDeg = elevation->second;
	auto clutter = parseRange(o.clutter, "--clutter");
	if (!clutter)
		return usage(clutter.error().message);
	c.params.layout.clutterMin = static_cast<int>(clutter->first);
	c.params.layout.clutterMax = static_cast<int>(clutter->second);
	Status valid = validateConfig(c);
	if (!valid)
		return usage(valid.error().message);

	auto progress = [&o](int objId, int imageId, int done, int total, const SynthImage &img) {
		if (o.quiet)
			return;
		if ((imageId + 1) % 10 != 0 && imageId + 1 != o.images)
			return;
		std::fprintf(stderr, "synth: object %d image %d/%d (%d/%d total), occlusion %.2f\n",
			     objId, imageId + 1, o.images, done, total, 1.0 - img.info.visibFract);
	};
	auto summary = runSynth(c, progress);
	if (!summary) {
		std::fprintf(stderr, "ihf synth: %s\n", summary.error().message.c_str());
		return summary.error().code == Errc::kInvalidArgument ? kExitUsage : kExitFailure;
	}
	printSummary(*summary);
	return kExitOk;
}

} // namespace

void addSynthCommand(CLI::App &root, Action &action)
{
	auto opts = std::make_shared<SynthOptions>();
	auto *cmd = root.add_subcommand(
		"synth",
		"Generate realistic synthetic depth test scenes (BOP layout, Kinect v1 or time-of-flight depth model): one "
		"scene per target object, the target on a cluttered table, occluded within a range, "
		"with ground truth and coarse detection boxes (boxes.json)");
	cmd->add_option("--models", opts->models, "BOP models folder (obj_NNNNNN.ply + models_info.json)")
		->required();
	cmd->add_option("--objects", opts->objects, "Target object ids, comma separated (e.g. 1,5,6)")
		->required();
	cmd->add_option("--out", opts->out, "Output dataset folder (must not exist unless --overwrite)")
		->required();
	cmd->add_option("--images", opts->images, "Images per object")->capture_default_str();
	cmd->add_option("--seed", opts->seed, "Random seed (same seed, same files)")->capture_default_str();
	cmd->add_option("--distance", opts->distance, "Camera to object centre, MIN:MAX mm")
		->capture_default_str();
	cmd->add_option("--occlusion", opts->occlusion, "Target occlusion 1 - visib_fract, MIN:MAX")
		->capture_default_str();
	cmd->add_option("--elevation", opts->elevation, "Camera elevation above the table, MIN:MAX degrees")
		->capture_default_str();
	cmd->add_option("--clutter", opts->clutter, "Clutter objects on the table, MIN:MAX")
		->capture_default_str();
	cmd->add_option("--wall", opts->wall, "Probability of a wall right behind the table")
		->capture_default_str();
	cmd->add_option("--camera", opts->camera, "BOP camera.json with the intrinsics (default Kinect v1 640x480)");
	cmd->add_option("--sensor", opts->sensor, "Depth model: kinect (structured light), tof (time of flight) or ideal (clean depth)")
		->capture_default_str();
	cmd->add_option("--depth-scale", opts->depthScale, "Depth PNG unit in mm: 1 or 0.1")
		->capture_default_str();
	cmd->add_option("--preview", opts->preview, "Also write false-colour depth pictures here");
	cmd->add_option("--preview-count", opts->previewCount, "Pictures per object with --preview")
		->capture_default_str();
	cmd->add_flag("--overwrite", opts->overwrite, "Replace an existing output folder");
	cmd->add_flag("--quiet", opts->quiet, "No progress lines");
	cmd->callback([&action, opts] { action = [opts] { return runSynthCommand(*opts); }; });
}

} // namespace ihf::app
