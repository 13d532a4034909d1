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

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "core/dataset/bop_dataset.h"
#include "core/dataset/atomic_file.h"
#include "core/dataset/bop_io.h"
#include "drivers/recording_reader.h"
#include "drivers/recording_writer.h"
#include "drivers/source_factory.h"
#include "firmware_app/command.h"

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

// The detections of one scene as `ihf run` box lines, one per recorded
// image (frame index = image id), numbers exact.
Status writeBoxLines(const std::string &out, const std::vector<Detection> &dets, int sceneId,
		     const std::map<int, SceneCamera> &images)
{
	auto num = [](std::string &s, double v) {
		char buf[32];
		auto [p, ec] = std::to_chars(buf, buf + sizeof(buf), v);
		s.append(buf, ec == std::errc() ? p : buf);
	};
	std::string text;
	for (const auto &[imId, cam] : images) {
		text += "{\"frame\":" + std::to_string(imId) + ",\"boxes\":[";
		bool first = true;
		for (const Detection &d : dets) {
			if (d.sceneId != sceneId || d.imageId != imId)
				continue;
			text += first ? "" : ",";
			first = false;
			text += "{\"obj_id\":" + std::to_string(d.categoryId) + ",\"bbox\":[";
			for (int k = 0; k < 4; ++k) {
				if (k)
					text += ",";
				num(text, d.bbox[k]);
			}
			text += "]}";
		}
		text += "]}\n";
	}
	return writeFileAtomic(out, text);
}

bool sameCamera(const SceneCamera &a, const SceneCamera &b)
{
	const CameraIntrinsics &p = a.intrinsics, &q = b.intrinsics;
	return p.fx == q.fx && p.fy == q.fy && p.cx == q.cx && p.cy == q.cy &&
	       a.depthScale == b.depthScale;
}

int recordFromBop(const RecordOptions &o)
{
	Expected<BopDataset> ds = BopDataset::open(o.fromBop, o.split);
	if (!ds) {
		std::fprintf(stderr, "ihf record: %s\n", ds.error().message.c_str());
		return kExitFailure;
	}
	int sceneId = o.scene;
	if (sceneId < 0) {
		const std::vector<int> ids = ds->sceneIds();
		if (ids.size() != 1) {
			std::string list;
			for (int id : ids)
				list += (list.empty() ? "" : ", ") + std::to_string(id);
			std::fprintf(stderr, "ihf record: %s/%s has %zu scenes (%s); choose one with --scene\n",
				     o.fromBop.c_str(), ds->split().c_str(), ids.size(), list.c_str());
			return kExitUsage;
		}
		sceneId = ids.front();
	}
	Expected<BopScene> scene = ds->loadScene(sceneId);
	if (!scene) {
		std::fprintf(stderr, "ihf record: %s\n", scene.error().message.c_str());
		return kExitFailure;
	}
	if (scene->cameras.empty()) {
		std::fprintf(stderr, "ihf record: %s: scene_camera.json lists no images\n",
			     ds->sceneDir(sceneId).string().c_str());
		return kExitFailure;
	}

	const auto &[firstId, firstCam] = *scene->cameras.begin();
	for (const auto &[imId, cam] : scene->cameras) {
		if (!sameCamera(cam, firstCam)) {
			std::fprintf(stderr,
				     "ihf record: %s: image %d has a different cam_K or depth_scale than image %d; "
				     "a recording has one camera (split the scene)\n",
				     (ds->sceneDir(sceneId) / "scene_camera.json").string().c_str(), imId, firstId);
			return kExitFailure;
		}
	}

	recording::RecordingHeader header;
	header.sensorId = "bop:" + std::filesystem::path(o.fromBop).filename().string() + "/" +
			  ds->split() + "/" + std::to_string(sceneId);
	header.intrinsics = firstCam.intrinsics;
	header.depthScale = firstCam.depthScale;
	RecordingWriterOptions wo;
	wo.compress = o.compress;
	Expected<RecordingWriter> writer = RecordingWriter::create(o.out, header, wo);
	if (!writer) {
		std::fprintf(stderr, "ihf record: %s\n", writer.error().message.c_str());
		return kExitFailure;
	}

	int64_t n = 0;
	for (const auto &[imId, cam] : scene->cameras) {
		const std::filesystem::path png = ds->depthPath(sceneId, imId);
		Expected<DepthImage16> depth = readDepthPng(png);
		if (!depth) {
			std::fprintf(stderr, "ihf record: %s\n", depth.error().message.c_str());
			return kExitFailure;
		}
		if (depth->width() != header.intrinsics.width || depth->height() != header.intrinsics.height) {
			std::fprintf(stderr, "ihf record: %s: image is %dx%d, camera.json says %dx%d\n",
				     png.string().c_str(), depth->width(), depth->height(),
				     header.intrinsics.width, header.intrinsics.height);
			return kExitFailure;
		}
		const int64_t t = std::llround(static_cast<double>(n) * 1e9 / o.fps);
		FrameStamp stamp{static_cast<uint64_t>(imId), t, t};
		if (Status s = writer->append(stamp, depth->view()); !s) {
			std::fprintf(stderr, "ihf record: %s\n", s.error().message.c_str());
			return kExitFailure;
		}
		++n;
	}
	if (Status s = writer->finish(); !s) {
		std::fprintf(stderr, "ihf record: %s\n", s.error().message.c_str());
		return kExitFailure;
	}
	std::fprintf(stderr, "ihf record: %lld frames of %s scene %d -> %s\n", static_cast<long long>(n),
		     o.fromBop.c_str(), sceneId, o.out.c_str());
	if (!o.boxesOut.empty()) {
		Expected<std::vector<Detection>> dets = readDetections(o.boxes);
		if (!dets) {
			std::fprintf(stderr, "ihf record: %s\n", dets.error().message.c_str());
			return kExitFailure;
		}
		if (Status st = writeBoxLines(o.boxesOut, *dets, sceneId, scene->cameras); !st) {
			std::fprintf(stderr, "ihf record: %s\n", st.error().message.c_str());
			return kExitFailure;
		}
		std::fprintf(stderr, "ihf record: box lines of %s -> %s\n", o.boxes.c_str(), o.boxesOut.c_str());
	}
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
