// SPDX-License-Identifier: MIT
// `ihf record`: makes .rec recordings, from a BOP dataset's depth images or
// from any frame source, and `ihf record info` summarises one.
//
// From BOP: the frames of one scene in image-id order; the frame index is
// the image id, intrinsics and depth scale come from scene_camera.json. A
// recording has one camera, so a scene whose cam_K or depth_scale changes
// between images is refused (naming both images) rather than recorded with
// a wrong calibration. BOP has no timestamps: frame i (0-based) gets device
// and host timestamps i / fps.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "drivers/recording_reader.h"
#include "drivers/recording_writer.h"
#include "drivers/source_factory.h"
#include "firmware_app/commands/bop_recording.h"
#include "firmware_app/commands/command.h"

namespace ihf::app {

namespace {

struct RecordOptions {
	std::string fromBop;
	std::string split;
	int scene = -1;
	std::string source;
	std::string out;
	int frames = 0;
	double fps = 30;
	int timeoutMs = 2000;
	int maxTimeouts = 5;
	bool compress = false;
	bool realTime = false;
	std::string boxes; // --from-bop: BOP detections of the scene
	std::string boxesOut; // written as `ihf run` box lines
};

int recordFromBop(const RecordOptions &o)
{
	BopRecordingRequest req;
	req.dataset = o.fromBop;
	req.split = o.split;
	req.sceneId = o.scene;
	req.out = o.out;
	req.fps = o.fps;
	req.compress = o.compress;
	req.boxes = o.boxes;
	req.boxesOut = o.boxesOut;
	Expected<BopRecordingResult> made = recordBopScene(req);
	if (!made) {
		std::fprintf(stderr, "ihf record: %s\n", made.error().message.c_str());
		return made.error().code == Errc::kInvalidArgument ? kExitUsage : kExitFailure;
	}
	std::fprintf(stderr, "ihf record: %lld frames of %s scene %d -> %s\n",
		     static_cast<long long>(made->frames), o.fromBop.c_str(), made->sceneId, o.out.c_str());
	if (!o.boxesOut.empty())
		std::fprintf(stderr, "ihf record: box lines of %s -> %s\n", o.boxes.c_str(), o.boxesOut.c_str());
	return kExitOk;
}

int recordFromSource(const RecordOptions &o)
{
	SourceOptions so;
	so.pacing = o.realTime ? Pacing::kRealTime : Pacing::kStep;
	Expected<std::unique_ptr<FrameSource>> made = makeFrameSource(o.source, so);
	if (!made) {
		std::fprintf(stderr, "ihf record: %s\n", made.error().message.c_str());
		return kExitUsage;
	}
	FrameSource &src = **made;
	if (Status s = src.open(); !s) {
		std::fprintf(stderr, "ihf record: %s\n", s.error().message.c_str());
		return kExitFailure;
	}
	if (src.info().live && o.frames <= 0) {
		std::fprintf(stderr, "ihf record: %s is a live device; give --frames N\n", o.source.c_str());
		return kExitUsage;
	}

	recording::RecordingHeader header;
	header.sensorId = src.info().sensorId;
	header.intrinsics = src.info().intrinsics;
	header.depthScale = src.info().depthScale;
	RecordingWriterOptions wo;
	wo.compress = o.compress;
	Expected<RecordingWriter> writer = RecordingWriter::create(o.out, header, wo);
	if (!writer) {
		std::fprintf(stderr, "ihf record: %s\n", writer.error().message.c_str());
		return kExitFailure;
	}
	if (Status s = src.start(); !s) {
		std::fprintf(stderr, "ihf record: %s\n", s.error().message.c_str());
		return kExitFailure;
	}

	int got = 0, timeoutsInARow = 0;
	Frame frame;
	while (o.frames <= 0 || got < o.frames) {
		Expected<FrameOutcome> r = src.next(frame, std::chrono::milliseconds(o.timeoutMs));
		if (!r) {
			std::fprintf(stderr, "ihf record: %s\n", r.error().message.c_str());
			return kExitFailure;
		}
		if (*r == FrameOutcome::kEndOfStream)
			break;
		if (*r == FrameOutcome::kTimeout) {
			if (++timeoutsInARow >= o.maxTimeouts) {
				std::fprintf(stderr, "ihf record: %s: no frame in %d tries of %d ms\n",
					     o.source.c_str(), timeoutsInARow, o.timeoutMs);
				return kExitFailure;
			}
			continue;
		}
		timeoutsInARow = 0;
		FrameStamp stamp{frame.index, frame.deviceTimestampNs, frame.hostTimestampNs};
		if (Status s = writer->append(stamp, frame.depth); !s) {
			std::fprintf(stderr, "ihf record: %s\n", s.error().message.c_str());
			return kExitFailure;
		}
		++got;
	}
	src.stop();
	if (Status s = writer->finish(); !s) {
		std::fprintf(stderr, "ihf record: %s\n", s.error().message.c_str());
		return kExitFailure;
	}
	const SourceCounters c = src.counters();
	std::fprintf(stderr, "ihf record: %d frames from %s -> %s (corrupt skipped %llu, dropped %llu)\n",
		     got, o.source.c_str(), o.out.c_str(), static_cast<unsigned long long>(c.corrupt),
		     static_cast<unsigned long long>(c.dropped));
	return kExitOk;
}

int runRecord(const RecordOptions &o)
{
	if (o.fromBop.empty() == o.source.empty()) {
		std::fprintf(stderr, "ihf record: give exactly one of --from-bop DATASET or --source URI "
				     "(or use `ihf record info FILE`)\n");
		return kExitUsage;
	}
	if (o.out.empty()) {
		std::fprintf(stderr, "ihf record: --out FILE is required\n");
		return kExitUsage;
	}
	if (o.boxes.empty() != o.boxesOut.empty() || (!o.boxes.empty() && o.fromBop.empty())) {
		std::fprintf(stderr, "ihf record: --boxes and --boxes-out go together, with --from-bop\n");
		return kExitUsage;
	}
	return o.fromBop.empty() ? recordFromSource(o) : recordFromBop(o);
}

int runRecordInfo(const std::string &file, bool verify)
{
	Expected<RecordingReader> reader = RecordingReader::open(file);
	if (!reader) {
		std::fprintf(stderr, "ihf record info: %s\n", reader.error().message.c_str());
		return kExitFailure;
	}
	const recording::RecordingHeader &h = reader->header();
	const CameraIntrinsics &k = h.intrinsics;
	std::printf("file          %s (%llu bytes)\n", file.c_str(),
		    static_cast<unsigned long long>(reader->fileSize()));
	std::printf("version       %u\n", h.version);
	std::printf("sensor        %s\n", h.sensorId.c_str());
	std::printf("size          %d x %d\n", k.width, k.height);
	std::printf("intrinsics    fx %.6f fy %.6f cx %.6f cy %.6f\n", k.fx, k.fy, k.cx, k.cy);
	std::printf("depth scale   %g mm per unit\n", h.depthScale);
	std::printf("frames        %zu\n", reader->frameCount());
	if (reader->indexed())
		std::printf("index         present\n");
	else
		std::printf("index         missing: %s; frames found by scanning, %llu trailing bytes unread\n",
			    reader->indexNote().c_str(), static_cast<unsigned long long>(reader->tailBytes()));
	if (reader->frameCount() == 0)
		return kExitOk;

	const uint64_t first = reader->entry(0).frameIndex;
	const uint64_t last = reader->entry(reader->frameCount() - 1).frameIndex;
	std::printf("frame index   %llu .. %llu (%llu missing in between)\n",
		    static_cast<unsigned long long>(first), static_cast<unsigned long long>(last),
		    static_cast<unsigned long long>(last - first + 1 - reader->frameCount()));
	if (!verify)
		return kExitOk;

	// Reads every frame: CRCs, encodings and the time span.
	Image<uint16_t> depth(k.width, k.height);
	size_t ok = 0, corrupt = 0, zlib = 0;
	int64_t t0 = 0, t1 = 0;
	for (size_t i = 0; i < reader->frameCount(); ++i) {
		recording::FrameRecord rec;
		const char *why = nullptr;
		Expected<FrameCheck> c = reader->read(i, rec, depth.view(), &why);
		if (!c) {
			std::fprintf(stderr, "ihf record info: %s\n", c.error().message.c_str());
			return kExitFailure;
		}
		if (*c == FrameCheck::kCorrupt) {
			std::printf("corrupt       frame %llu (position %zu): %s\n",
				    static_cast<unsigned long long>(reader->entry(i).frameIndex), i, why);
			++corrupt;
			continue;
		}
		if (ok == 0)
			t0 = rec.hostTimestampNs;
		t1 = rec.hostTimestampNs;
		zlib += rec.encoding == recording::Encoding::kZlib;
		++ok;
	}
	std::printf("checked       %zu ok, %zu corrupt; %zu zlib, %zu raw\n", ok, corrupt, zlib, ok - zlib);
	std::printf("duration      %.3f s (host timestamps)\n", (t1 - t0) * 1e-9);
	return corrupt ? kExitFailure : kExitOk;
}

} // namespace

void addRecordCommand(CLI::App &root, Action &action)
{
	auto o = std::make_shared<RecordOptions>();
	auto *cmd = root.add_subcommand(
		"record", "Make an ihf recording (.rec) from a BOP dataset or a frame source");
	cmd->require_subcommand(0, 1);
	cmd->add_option("--from-bop", o->fromBop, "BOP dataset root (frames of one scene, image order)");
	cmd->add_option("--split", o->split, "BOP split (default: test, val or train, the first present)");
	cmd->add_option("--scene", o->scene, "BOP scene id (needed when the split has several)");
	cmd->add_option("--source", o->source, std::string("frame source URI: ") + frameSourceUriHelp());
	cmd->add_option("--out", o->out, "recording to write (atomically)");
	cmd->add_option("--frames", o->frames, "frames to record from --source (0 = until the stream ends)")
		->check(CLI::NonNegativeNumber);
	cmd->add_option("--fps", o->fps, "--from-bop: frame rate for the synthetic timestamps")
		->check(CLI::PositiveNumber);
	cmd->add_option("--timeout-ms", o->timeoutMs, "--source: wait per frame")->check(CLI::PositiveNumber);
	cmd->add_option("--max-timeouts", o->maxTimeouts, "--source: give up after this many timeouts in a row")
		->check(CLI::PositiveNumber);
	cmd->add_flag("--compress", o->compress, "zlib-compress each frame");
	cmd->add_option("--boxes", o->boxes, "--from-bop: BOP detections (e.g. DATASET/boxes.json) to convert");
	cmd->add_option("--boxes-out", o->boxesOut, "--from-bop: write them as `ihf run` box lines (JSON lines)");
	cmd->add_flag("--real-time", o->realTime, "--source files: play at recorded speed instead of stepping");
	cmd->callback([&action, o, cmd] {
		if (cmd->get_subcommands().empty())
			action = [o] { return runRecord(*o); };
	});

	auto file = std::make_shared<std::string>();
	auto noVerify = std::make_shared<bool>(false);
	auto *info = cmd->add_subcommand(
		"info", "Summarise a recording: header, frames, index; reads every frame to check its CRC");
	info->add_option("file", *file, "recording (.rec)")->required();
	info->add_flag("--no-verify", *noVerify, "header and index only, do not read the frames");
	info->callback([&action, file, noVerify] {
		action = [file, noVerify] { return runRecordInfo(*file, !*noVerify); };
	});
}

} // namespace ihf::app
