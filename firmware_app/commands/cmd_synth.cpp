// SPDX-License-Identifier: MIT
// `ihf synth`: realistic synthetic depth test scenes in BOP layout, and with
// --sequence 30 Hz depth sequences of a table seen by a moving camera.

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <cmath>
#include <string>
#include <vector>

#include "core/dataset/bop_io.h"
#include "core/geometry/ply_loader.h"
#include "core/synth/dataset_staging.h"
#include "core/synth/household_objects.h"
#include "core/synth/sequence_dataset.h"
#include "core/synth/synth_dataset.h"
#include "firmware_app/commands/bop_recording.h"
#include "firmware_app/commands/command.h"

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
	// --make-object
	std::string makeObject;
	int objectId = 0;
	bool withoutPart = false;
	// --sequence
	bool sequence = false;
	int sequences = 1;
	int frames = 300;
	std::string perFrame = "3:8";
	std::string motion = "mixed";
	double miss = 0.03;
	double change = 0.5;
	double maxSpeed = 0.5; // m/s
	double maxTurn = 90;   // deg/s
	// Options given on the command line (defaults differ between the modes).
	std::vector<std::string> given;
	bool has(const std::string &flag) const
	{
		return std::find(given.begin(), given.end(), flag) != given.end();
	}
};

// Options of one mode that the other does not take.
const char *const kImageOnly[] = {"--images", "--occlusion", "--preview", "--preview-count"};
const char *const kSequenceOnly[] = {"--sequences", "--frames", "--per-frame", "--motion",
				     "--miss", "--change", "--max-speed", "--max-turn"};

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

int runSequenceCommand(const SynthOptions &o);

// --make-object: writes MODELS/obj_NNNNNN.ply and its models_info.json entry
// (the file made or updated; other entries kept).
int runMakeObjectCommand(const SynthOptions &o)
{
	if (o.models.empty() || o.objectId <= 0)
		return usage("--make-object needs --models DIR and --id N (N > 0)");
	for (const std::string &flag : o.given)
		if (flag != "--make-object" && flag != "--models" && flag != "--id" && flag != "--without-part" &&
		    flag != "--quiet")
			return usage(flag + ": not an option of --make-object");
	const std::optional<HouseholdObject> object = householdObjectNamed(o.makeObject);
	if (!object)
		return usage("--make-object '" + o.makeObject + "': expected cup, camera or bottle");
	const Mesh mesh = makeHouseholdObject(*object, !o.withoutPart);
	const std::filesystem::path dir = o.models;
	std::error_code ec;
	std::filesystem::create_directories(dir, ec);
	if (ec) {
		std::fprintf(stderr, "ihf synth: %s: %s\n", dir.c_str(), ec.message().c_str());
		return kExitFailure;
	}
	const std::filesystem::path ply = dir / ("obj_" + sixDigits(o.objectId) + ".ply");
	const std::filesystem::path infoFile = dir / "models_info.json";
	std::map<int, ModelInfo> info;
	if (std::filesystem::exists(infoFile)) {
		auto read = readModelsInfo(infoFile);
		if (!read) {
			std::fprintf(stderr, "ihf synth: %s\n", read.error().message.c_str());
			return kExitFailure;
		}
		info = std::move(*read);
	}
	const Aabb box = boundingBox(mesh);
	ModelInfo entry;
	entry.objId = o.objectId;
	entry.diameter = meshDiameter(mesh);
	entry.min = box.min.cast<double>();
	entry.size = box.size().cast<double>();
	info[o.objectId] = entry;
	if (Status s = savePly(ply, mesh); !s) {
		std::fprintf(stderr, "ihf synth: %s\n", s.error().message.c_str());
		return kExitFailure;
	}
	if (Status s = writeModelsInfo(infoFile, info); !s) {
		std::fprintf(stderr, "ihf synth: %s\n", s.error().message.c_str());
		return kExitFailure;
	}
	if (!o.quiet)
		std::fprintf(stderr, "synth: %s -> %s (%zu vertices, %zu faces, diameter %.1f mm)\n",
			     o.makeObject.c_str(), ply.c_str(), mesh.vertices.size(), mesh.faces.size(),
			     entry.diameter);
	return kExitOk;
}

int runSynthCommand(const SynthOptions &o)
{
	if (!o.makeObject.empty())
		return runMakeObjectCommand(o);
	if (o.objects.empty() || o.out.empty() || o.models.empty())
		return usage("--models, --objects and --out are required");
	if (o.sequence)
		return runSequenceCommand(o);
	for (const char *flag : kSequenceOnly)
		if (o.has(flag))
			return usage(std::string(flag) + ": only with --sequence");
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

int runSequenceCommand(const SynthOptions &o)
{
	for (const char *flag : kImageOnly)
		if (o.has(flag))
			return usage(std::string(flag) + ": not an option of --sequence");
	SequenceConfig c;
	c.modelsDir = o.models;
	c.outDir = o.out;
	c.cameraFile = o.camera;
	c.sequences = o.sequences;
	c.overwrite = o.overwrite;
	SequenceParams &p = c.params;
	p.frames = o.frames;
	p.synth.seed = o.seed;
	p.synth.depthScale = o.depthScale;
	p.synth.layout.wallProbability = o.wall;
	p.detector.missProbability = o.miss;
	p.changeProbability = o.change;
	p.path.maxSpeedMmS = o.maxSpeed * 1000.0;
	p.path.maxTurnDegS = o.maxTurn;
	const std::optional<SensorModel> model = sensorModelNamed(o.sensor);
	if (!model)
		return usage("--sensor '" + o.sensor + "': expected kinect, tof or ideal");
	p.synth.model = *model;
	const std::optional<CameraMotion> motion = cameraMotionNamed(o.motion);
	if (!motion)
		return usage("--motion '" + o.motion + "': expected handheld, robot or mixed");
	p.motion = *motion;

	auto ids = parseIdList(o.objects, "--objects");
	if (!ids)
		return usage(ids.error().message);
	c.objects = *ids;
	auto perFrame = parseRange(o.has("--per-frame") ? o.perFrame : "3:8", "--per-frame");
	if (!perFrame)
		return usage(perFrame.error().message);
	if (perFrame->first != std::floor(perFrame->first) || perFrame->second != std::floor(perFrame->second))
		return usage("--per-frame '" + o.perFrame + "': expected whole numbers MIN:MAX");
	p.perFrameMin = static_cast<int>(perFrame->first);
	p.perFrameMax = static_cast<int>(perFrame->second);
	if (!o.has("--per-frame")) {
		// The default asks for 3 to 8 targets, as many as there are.
		const int n = static_cast<int>(c.objects.size());
		p.perFrameMin = std::min(p.perFrameMin, n);
		p.perFrameMax = std::min(p.perFrameMax, n);
	}
	auto distance = parseRange(o.has("--distance") ? o.distance : "600:1100", "--distance");
	if (!distance)
		return usage(distance.error().message);
	p.path.distanceMin = distance->first;
	p.path.distanceMax = distance->second;
	auto elevation = parseRange(o.has("--elevation") ? o.elevation : "20:55", "--elevation");
	if (!elevation)
		return usage(elevation.error().message);
	p.path.elevationMinDeg = elevation->first;
	p.path.elevationMaxDeg = elevation->second;
	auto clutter = parseRange(o.clutter, "--clutter");
	if (!clutter)
		return usage(clutter.error().message);
	p.synth.layout.clutterMin = static_cast<int>(clutter->first);
	p.synth.layout.clutterMax = static_cast<int>(clutter->second);
	if (Status valid = validateSequenceConfig(c); !valid)
		return usage(valid.error().message);

	auto progress = [&o](int seq, int frame, int frames) {
		if (o.quiet || ((frame + 1) % 30 != 0 && frame + 1 != frames))
			return;
		std::fprintf(stderr, "synth: sequence %d frame %d/%d\n", seq, frame + 1, frames);
	};
	// Each scene also as a recording with its `ihf run` box lines, the
	// frames 1 / fps apart.
	auto record = [&p, &o](const std::filesystem::path &root, int sceneId) -> Status {
		const std::filesystem::path dir = root / "recordings";
		std::error_code ec;
		std::filesystem::create_directories(dir, ec);
		if (ec)
			return makeError(Errc::kIo, dir.string() + ": " + ec.message());
		BopRecordingRequest req;
		req.dataset = root;
		req.split = "test";
		req.sceneId = sceneId;
		req.out = dir / (sixDigits(sceneId) + ".rec");
		req.fps = p.fps;
		req.compress = true;
		req.sensorId = std::string("ihf-synth:") + sensorModelName(p.synth.model) + "/" +
			       std::to_string(sceneId);
		req.boxes = root / "boxes.json";
		req.boxesOut = dir / (sixDigits(sceneId) + ".boxes.jsonl");
		auto made = recordBopScene(req);
		if (!made)
			return made.error();
		if (!o.quiet)
			std::fprintf(stderr, "synth: sequence %d: %lld frames -> recordings/%s.rec\n", sceneId,
				     static_cast<long long>(made->frames), sixDigits(sceneId).c_str());
		return {};
	};
	auto summary = runSynthSequences(c, progress, record);
	if (!summary) {
		std::fprintf(stderr, "ihf synth: %s\n", summary.error().message.c_str());
		return summary.error().code == Errc::kInvalidArgument ? kExitUsage : kExitFailure;
	}
	const SequenceSummary &s = *summary;
	std::fprintf(stderr, "synth: %d sequences, %d frames in %.1f s (%.2f s/frame), %d visible targets, %d boxes\n",
		     s.sequences, s.frames, s.seconds, s.seconds / std::max(s.frames, 1), s.instances, s.boxes);
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
	cmd->add_flag("--sequence", opts->sequence,
		      "Make 30 Hz depth sequences instead: a table with several targets, a moving camera, "
		      "objects moved, taken away or put down; one scene per sequence, and a recording each");
	cmd->add_option("--models", opts->models, "BOP models folder (obj_NNNNNN.ply + models_info.json)");
	cmd->add_option("--objects", opts->objects, "Target object ids, comma separated (e.g. 1,5,6)");
	cmd->add_option("--out", opts->out, "Output dataset folder (must not exist unless --overwrite)");
	cmd->add_option("--make-object", opts->makeObject,
			"Write a procedural object instead (cup, camera or bottle: nearly symmetric, told apart by a "
			"handle, a lens, a pump nozzle) as --models/obj_<--id>.ply with its models_info.json entry");
	cmd->add_option("--id", opts->objectId, "--make-object: the object's id");
	cmd->add_flag("--without-part", opts->withoutPart,
		      "--make-object: the body alone, without the small part (to find where the part shows)");
	cmd->add_option("--images", opts->images, "Images per object")->capture_default_str();
	cmd->add_option("--seed", opts->seed, "Random seed (same seed, same files)")->capture_default_str();
	cmd->add_option("--distance", opts->distance,
			"Camera to object centre, MIN:MAX mm (--sequence: to the point looked at, default 600:1100)")
		->capture_default_str();
	cmd->add_option("--occlusion", opts->occlusion, "Target occlusion 1 - visib_fract, MIN:MAX")
		->capture_default_str();
	cmd->add_option("--elevation", opts->elevation,
			"Camera elevation above the table, MIN:MAX degrees (--sequence: default 20:55)")
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
	cmd->add_option("--sequences", opts->sequences, "--sequence: sequences (scenes 1..N)")->capture_default_str();
	cmd->add_option("--frames", opts->frames, "--sequence: frames per sequence (30 per second)")
		->capture_default_str();
	cmd->add_option("--per-frame", opts->perFrame,
			"--sequence: target objects on the table, MIN:MAX (default 3:8, at most the --objects given)");
	cmd->add_option("--motion", opts->motion, "--sequence: camera motion: handheld, robot or mixed (per sequence)")
		->capture_default_str();
	cmd->add_option("--miss", opts->miss, "--sequence: share of boxes the detector misses")->capture_default_str();
	cmd->add_option("--change", opts->change,
			"--sequence: probability that an object is also taken away or put down")
		->capture_default_str();
	cmd->add_option("--max-speed", opts->maxSpeed, "--sequence: camera speed limit, m/s")->capture_default_str();
	cmd->add_option("--max-turn", opts->maxTurn, "--sequence: camera turn rate limit, deg/s")->capture_default_str();
	cmd->add_flag("--overwrite", opts->overwrite, "Replace an existing output folder");
	cmd->add_flag("--quiet", opts->quiet, "No progress lines");
	cmd->callback([&action, opts, cmd] {
		opts->given.clear();
		for (const CLI::Option *opt : cmd->get_options())
			if (opt->count() > 0)
				opts->given.push_back(opt->get_name());
		action = [opts] { return runSynthCommand(*opts); };
	});
}

} // namespace ihf::app
