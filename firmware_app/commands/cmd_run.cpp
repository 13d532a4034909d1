// SPDX-License-Identifier: MIT
// `ihf run`: the on-device loop. Frames from a source URI, boxes per frame
// from an upstream detector (JSON lines), a pose per box with its object's
// forest, poses out as JSON lines; late frames dropped, periodic stats,
// source errors retried, clean stop on SIGINT/SIGTERM (config/device.toml).

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include "core/model/forest_file.h"
#ifdef IHF_HAVE_OPENNI2
#include "drivers/openni2_source.h"
#endif
#include "drivers/source_factory.h"
#include "firmware_app/runtime/box_feed.h"
#include "firmware_app/commands/command.h"
#include "firmware_app/config/pipeline_config.h"
#include "firmware_app/runtime/pose_output.h"
#include "firmware_app/runtime/pose_pipeline.h"
#include "firmware_app/runtime/pose_stage.h"
#include "firmware_app/runtime/run_loop.h"
#include "firmware_app/runtime/service_notify.h"
#include "firmware_app/runtime/shutdown_signal.h"
#include "firmware_app/runtime/usb_presence.h"
#include "firmware_app/runtime/vis_writer.h"

namespace ihf::app {

namespace {

struct RunOptions {
	std::string config;
	std::string source;
	std::string boxes;
	std::string out;
	std::string vis;
	std::vector<std::string> forests;
	int64_t frames = -1;
	bool realTime = false;
	bool step = false;
	double statsInterval = -1;
	double dropFramesOlderThanMs = -1; // --drop-frames-older-than-ms
	double estimateBudgetMs = -1; // --budget-ms: the frame's estimation budget
	std::string boxKind;          // --box-kind
	bool noTracking = false;      // --no-tracking
};

int failWith(const std::string &message, int code = kExitFailure)
{
	std::fprintf(stderr, "ihf run: %s\n", message.c_str());
	return code;
}

int runRun(const RunOptions &o)
{
	// First, before anything could start a thread: signals become a file descriptor.
	ShutdownSignal shutdown;
	if (!shutdown.valid())
		std::fprintf(stderr, "ihf run: note: no signalfd; SIGINT/SIGTERM end the process at once\n");

	Expected<RunSettings> loaded = loadRunConfig(o.config);
	if (!loaded)
		return failWith(loaded.error().message);
	RunSettings rs = *loaded;
	if (!o.source.empty())
		rs.sourceUri = o.source;
	if (!o.boxes.empty())
		rs.boxes = o.boxes;
	if (!o.out.empty())
		rs.poses = o.out;
	if (o.frames >= 0)
		rs.maxFrames = o.frames;
	if (o.realTime)
		rs.realTime = true;
	if (o.step)
		rs.realTime = false;
	if (o.statsInterval >= 0)
		rs.statsIntervalS = o.statsInterval;
	if (o.dropFramesOlderThanMs >= 0)
		rs.dropFramesOlderThanMs = o.dropFramesOlderThanMs;
	if (o.estimateBudgetMs >= 0)
		rs.estimationBudgetMs = o.estimateBudgetMs;
	if (!o.boxKind.empty()) {
		Expected<BoxKind> kind = parseBoxKind(o.boxKind, "--box-kind");
		if (!kind)
			return failWith(kind.error().message, kExitUsage);
		rs.boxKind = *kind;
	}
	if (!o.forests.empty()) {
		Expected<std::map<int, std::filesystem::path>> given = parseForestOptions(o.forests);
		if (!given)
			return failWith(given.error().message, kExitUsage);
		rs.forests = *given;
	}
	if (rs.sourceUri.empty())
		return failWith(o.config + ": no [source] uri (or give --source URI)", kExitUsage);
	if (rs.forests.empty())
		return failWith(o.config + ": no [objects] (object id = forest file)", kExitUsage);

	Expected<EstimateSettings> es = loadEstimateConfig(rs.estimateConfig);
	if (!es)
		return failWith(es.error().message);
	if (rs.iterations)
		es->estimator.iterations = *rs.iterations;
	if (rs.estimationBudgetMs)
		es->estimator.frameBudgetMs = static_cast<float>(*rs.estimationBudgetMs);
	else if (rs.estimateConfig.empty())
		es->estimator.frameBudgetMs = kDeviceFrameBudgetMs;
	if (rs.boxKind)
		useBoxKind(*es, *rs.boxKind);

	// Tracking follows each object from frame to frame; --vis pictures the
	// cold estimator's iterations, so it detects every box.
	const bool tracking = rs.tracking.enabled && !o.noTracking && o.vis.empty();
	SteadyPacingClock clock;
	Expected<std::unique_ptr<PosePipeline>> pipeline =
		PosePipeline::create(rs.forests, *es, tracking ? &rs.tracking : nullptr, clock, "ihf run");
	if (!pipeline)
		return failWith(pipeline.error().message);
	PosePipeline &poses = **pipeline;

	// Reconnecting closes and reopens the source: OpenNI2 must not unload
	// its drivers in between (see OpenNi2Session).
#ifdef IHF_HAVE_OPENNI2
	std::optional<OpenNi2Session> openni2;
	if (rs.sourceUri.rfind("openni2:", 0) == 0)
		openni2.emplace();
#endif

	SourceOptions so;
	so.pacing = rs.realTime ? Pacing::kRealTime : Pacing::kStep;
	so.speed = rs.speed;
	Expected<std::unique_ptr<FrameSource>> source = makeFrameSource(rs.sourceUri, so);
	if (!source)
		return failWith(source.error().message, kExitUsage);

	Expected<std::unique_ptr<BoxFeed>> feed = BoxFeed::open(rs.boxes, &shutdown);
	if (!feed)
		return failWith(feed.error().message);
	Expected<std::unique_ptr<PoseOutput>> output = PoseOutput::open(rs.poses, feed->get());
	if (!output)
		return failWith(output.error().message);

	PoseStage stage(poses.frames(), **feed, **output, clock, std::chrono::milliseconds(rs.boxesTimeoutMs));
	std::unique_ptr<VisWriter> vis;
	if (!o.vis.empty()) {
		Expected<std::unique_ptr<VisWriter>> v = VisWriter::create(o.vis, es->limits);
		if (!v)
			return failWith(v.error().message);
		vis = std::move(v.value());
		poses.estimator().setObserver(vis.get());
		poses.frames().setBoxObserver(vis.get());
	}

	RunLoopConfig lc;
	lc.realTime = rs.realTime;
	lc.speed = rs.speed;
	lc.timeout = std::chrono::milliseconds(rs.timeoutMs);
	lc.maxRetries = rs.maxRetries;
	lc.backoff = std::chrono::milliseconds(rs.retryBackoffMs);
	lc.backoffMax = std::chrono::milliseconds(rs.retryBackoffMaxMs);
	lc.frameBudget = std::chrono::nanoseconds(static_cast<int64_t>(rs.dropFramesOlderThanMs * 1e6));
	lc.statsInterval = std::chrono::nanoseconds(static_cast<int64_t>(rs.statsIntervalS * 1e9));
	lc.maxFrames = static_cast<uint64_t>(rs.maxFrames);

	RunLoop loop(**source, stage, clock, lc, &shutdown, stderr);
	std::unique_ptr<LibusbEnumerator> usb;
	std::unique_ptr<UsbSensorPresence> presence;
	if (!rs.usbWatch.empty()) {
		Expected<UsbSensorFilter> filter = parseUsbSensorFilter(rs.usbWatch);
		if (!filter)
			return failWith(o.config + ": source.usb_watch: " + filter.error().message, kExitUsage);
		Expected<std::unique_ptr<LibusbEnumerator>> e = LibusbEnumerator::create();
		if (!e) {
			std::fprintf(stderr, "ihf run: note: %s; running without the USB watch\n",
				     e.error().message.c_str());
		} else {
			usb = std::move(e.value());
			presence = std::make_unique<UsbSensorPresence>(*usb, *filter);
			loop.setPresence(presence.get());
		}
	}
	ServiceNotifier notifier;
	loop.setHeartbeat(&notifier);
	const RunEnd end = loop.run();
	notifier.stopping();

	Status finished = (*output)->finish();
	const BoxFeedCounters &fc = (*feed)->counters();
	std::fprintf(stderr, "ihf run: %s; %s; box lines %llu skipped %llu malformed %llu%s\n", runEndName(end),
		     loop.statsLine().c_str(), static_cast<unsigned long long>(fc.lines),
		     static_cast<unsigned long long>(fc.skipped), static_cast<unsigned long long>(fc.malformed),
		     shutdown.signal() ? (shutdown.signal() == SIGINT ? "; on SIGINT" : "; on SIGTERM") : "");
	if (vis)
		std::fprintf(stderr, "ihf run: %llu pictures in %s\n",
			     static_cast<unsigned long long>(vis->written()), o.vis.c_str());
	if (end == RunEnd::kSourceFailed || end == RunEnd::kProcessFailed)
		return failWith(loop.failure());
	if (!finished)
		return failWith(finished.error().message);
	return kExitOk;
}

} // namespace

void addRunCommand(CLI::App &root, Action &action)
{
	auto o = std::make_shared<RunOptions>();
	auto *cmd = root.add_subcommand(
		"run", "On-device loop: frames + boxes (JSON lines) in, poses (JSON lines) out");
	cmd->add_option("--config", o->config, "device configuration (TOML), e.g. config/device.toml")
		->required()
		->check(CLI::ExistingFile);
	cmd->add_option("--source", o->source, std::string("frame source URI (overrides [source] uri): ") +
							frameSourceUriHelp());
	cmd->add_option("--boxes", o->boxes, "boxes input: stdin, file:PATH or unix:PATH (overrides [boxes] input)");
	cmd->add_option("--out", o->out, "poses output: stdout, file:PATH or socket (overrides [output] poses)");
	cmd->add_option("--forest", o->forests, "OBJ_ID=FILE.ihf, one per object (replaces [objects])");
	cmd->add_option("--frames", o->frames, "stop after N frames (overrides [run] max_frames)")
		->check(CLI::NonNegativeNumber);
	cmd->add_flag("--real-time", o->realTime, "recordings: replay at recorded speed (late frames dropped)");
	cmd->add_flag("--step", o->step, "recordings: every frame in turn, none dropped");
	cmd->add_option("--drop-frames-older-than-ms", o->dropFramesOlderThanMs,
			"real time: drop frames older than this at their turn (overrides [run] drop_frames_older_than_ms; "
			"0: never)")
		->check(CLI::NonNegativeNumber);
	cmd->add_option("--budget-ms", o->estimateBudgetMs,
			"estimation time per frame, shared by its boxes (overrides [estimate] estimation_budget_ms; 0: unlimited)")
		->check(CLI::NonNegativeNumber);
	cmd->add_option("--box-kind", o->boxKind,
			"what the boxes bound: amodal (the whole object) or modal (its visible part, as most "
			"detectors give); overrides [boxes] kind")
		->check(CLI::IsMember({"amodal", "modal"}));
	cmd->add_flag("--no-tracking", o->noTracking,
		      "estimate every box afresh (no frame-to-frame tracking; overrides [tracking] enabled)");
	cmd->add_option("--stats-interval", o->statsInterval, "seconds between stats lines on stderr (0: end only)")
		->check(CLI::NonNegativeNumber);
	cmd->add_option("--vis", o->vis, "write PNGs of each box's depth crop with the hypothesis silhouette per iteration");
	cmd->callback([o, &action] { action = [o] { return runRun(*o); }; });
}

} // namespace ihf::app
