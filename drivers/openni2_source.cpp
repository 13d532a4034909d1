// SPDX-License-Identifier: MIT
#include "drivers/openni2_source.h"

#include <cmath>
#include <cstring>

#include <OpenNI.h>

#include "drivers/clock.h"

namespace ihf {

struct OpenNi2Source::State {
	bool initialised = false;
	openni::Device device;
	openni::VideoStream stream;
	bool isFile = false;
};

namespace {

std::string oniError(const char *what)
{
	std::string s = what;
	// OpenNI2's extended error is tab-indented and newline-terminated.
	std::string ext = openni::OpenNI::getExtendedError() ? openni::OpenNI::getExtendedError() : "";
	const size_t b = ext.find_first_not_of(" \t\r\n");
	const size_t e = ext.find_last_not_of(" \t\r\n");
	if (b != std::string::npos) {
		ext = ext.substr(b, e - b + 1);
		for (char &c : ext)
			if (c == '\n' || c == '\t')
				c = ' ';
		s += ": " + ext;
	}
	return s;
}

} // namespace

OpenNi2Session::OpenNi2Session() : ok_(openni::OpenNI::initialize() == openni::STATUS_OK) {}

OpenNi2Session::~OpenNi2Session()
{
	if (ok_)
		openni::OpenNI::shutdown();
}

Expected<std::vector<std::string>> listOpenNi2Devices()
{
	if (openni::OpenNI::initialize() != openni::STATUS_OK)
		return makeError(Errc::kIo, oniError("OpenNI2 initialisation failed"));
	openni::Array<openni::DeviceInfo> list;
	openni::OpenNI::enumerateDevices(&list);
	std::vector<std::string> out;
	for (int i = 0; i < list.getSize(); ++i)
		out.push_back(std::string(list[i].getUri()) + " (" + list[i].getVendor() + " " + list[i].getName() + ")");
	openni::OpenNI::shutdown();
	return out;
}

OpenNi2Source::OpenNi2Source(std::string deviceUri, OpenNi2SourceOptions options, std::string uri)
	: deviceUri_(std::move(deviceUri)), options_(std::move(options)),
	  clock_(options_.clock ? options_.clock : &steadyClock_), pacer_(*clock_, options_.speed)
{
	info_.uri = uri.empty() ? "openni2:" + deviceUri_ : std::move(uri);
}

OpenNi2Source::~OpenNi2Source()
{
	close();
}

void OpenNi2Source::close()
{
	if (!state_)
		return;
	if (state_->stream.isValid()) {
		state_->stream.stop();
		state_->stream.destroy();
	}
	if (state_->device.isValid())
		state_->device.close();
	if (state_->initialised)
		openni::OpenNI::shutdown();
	state_.reset();
	started_ = false;
}

Status OpenNi2Source::open()
{
	close();
	state_ = std::make_unique<State>();
	auto fail = [this](Errc code, const char *what) -> Status {
		Error e = makeError(code, info_.uri + ": " + oniError(what));
		close();
		return e;
	};

	if (options_.realTime && !ReplayPacer::validSpeed(options_.speed))
		return fail(Errc::kInvalidArgument, "playback speed must be > 0");
	if (openni::OpenNI::initialize() != openni::STATUS_OK)
		return fail(Errc::kIo, "OpenNI2 initialisation failed");
	state_->initialised = true;

	const char *uri = deviceUri_.empty() ? openni::ANY_DEVICE : deviceUri_.c_str();
	if (state_->device.open(uri) != openni::STATUS_OK)
		return fail(Errc::kNotFound, deviceUri_.empty() ? "no OpenNI2 device found"
								: "cannot open OpenNI2 device");
	state_->isFile = state_->device.isFile();
	if (!state_->device.hasSensor(openni::SENSOR_DEPTH))
		return fail(Errc::kUnsupported, "device has no depth sensor");
	if (state_->stream.create(state_->device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
		return fail(Errc::kIo, "cannot create the depth stream");

	if (state_->isFile) {
		openni::PlaybackControl *playback = state_->device.getPlaybackControl();
		if (!playback)
			return fail(Errc::kIo, "file device without playback control");
		// -1 is OpenNI2's manual speed: the next frame is produced on request
		// (see the header for why realTime paces it here). With repeat on,
		// after the last frame the player rewinds and waits for a request
		// that never comes; with it off it would spin until closed.
		if (playback->setSpeed(-1.0f) != openni::STATUS_OK ||
		    playback->setRepeatEnabled(true) != openni::STATUS_OK)
			return fail(Errc::kIo, "cannot set playback speed / repeat");
		fileFrames_ = playback->getNumberOfFrames(state_->stream);
	}

	const openni::VideoMode mode = state_->stream.getVideoMode();
	switch (mode.getPixelFormat()) {
	case openni::PIXEL_FORMAT_DEPTH_1_MM:
		info_.depthScale = 1.0;
		break;
	case openni::PIXEL_FORMAT_DEPTH_100_UM:
		info_.depthScale = 0.1;
		break;
	default:
		return fail(Errc::kUnsupported, "depth pixel format is neither 1 mm nor 100 um");
	}
	const int w = mode.getResolutionX(), h = mode.getResolutionY();
	if (w <= 0 || h <= 0)
		return fail(Errc::kUnsupported, "depth stream reports no resolution");

	if (options_.intrinsics) {
		info_.intrinsics = *options_.intrinsics;
		if (info_.intrinsics.width != w || info_.intrinsics.height != h)
			return fail(Errc::kInvalidArgument, "given intrinsics do not match the stream size");
	} else {
		const double hfov = state_->stream.getHorizontalFieldOfView();
		const double vfov = state_->stream.getVerticalFieldOfView();
		if (!(hfov > 0 && hfov < M_PI) || !(vfov > 0 && vfov < M_PI))
			return fail(Errc::kUnsupported, "stream reports no field of view; give intrinsics");
		info_.intrinsics.width = w;
		info_.intrinsics.height = h;
		info_.intrinsics.fx = w / (2.0 * std::tan(hfov / 2));
		info_.intrinsics.fy = h / (2.0 * std::tan(vfov / 2));
		info_.intrinsics.cx = (w - 1) / 2.0;
		info_.intrinsics.cy = (h - 1) / 2.0;
	}

	const openni::DeviceInfo &di = state_->device.getDeviceInfo();
	info_.sensorId = std::string("OpenNI2 ") + di.getVendor() + " " + di.getName() + " (" +
			 di.getUri() + ")";
	info_.live = !state_->isFile;
	counters_ = {};
	fileFramesRead_ = 0;
	lastIndex_.reset();
	pending_ = false;
	pacer_.reset();
	return {};
}

Status OpenNi2Source::start()
{
	if (!state_)
		return makeError(Errc::kInvalidArgument, info_.uri + ": start() before open()");
	const CameraIntrinsics &k = info_.intrinsics;
	if (buffer_.width() != k.width || buffer_.height() != k.height)
		buffer_ = Image<uint16_t>(k.width, k.height);
	if (state_->stream.start() != openni::STATUS_OK)
		return makeError(Errc::kIo, info_.uri + ": " + oniError("cannot start the depth stream"));
	pacer_.reset(); // pacing restarts at the next frame
	started_ = true;
	return {};
}

void OpenNi2Source::stop()
{
	if (state_ && started_)
		state_->stream.stop();
	started_ = false;
}

Expected<FrameOutcome> OpenNi2Source::next(Frame &frame, std::chrono::nanoseconds timeout)
{
	if (!started_)
		return makeError(Errc::kInvalidArgument, info_.uri + ": next() before start()");
	if (!pending_) {
		if (state_->isFile && fileFramesRead_ >= fileFrames_)
			return FrameOutcome::kEndOfStream;
		Expected<FrameOutcome> read = readFrame(timeout);
		if (!read || *read != FrameOutcome::kFrame)
			return read;
	}

	if (state_->isFile && options_.realTime && !pacer_.waitFor(pendingDeviceNs_, timeout)) {
		++counters_.timeouts;
		return FrameOutcome::kTimeout;
	}

	pending_ = false;
	frame.index = pendingIndex_;
	frame.deviceTimestampNs = pendingDeviceNs_;
	frame.hostTimestampNs = pendingHostNs_;
	frame.intrinsics = info_.intrinsics;
	frame.depthScale = info_.depthScale;
	frame.depth = buffer_.view();
	if (lastIndex_ && frame.index > *lastIndex_ + 1)
		counters_.dropped += frame.index - *lastIndex_ - 1;
	lastIndex_ = frame.index;
	++counters_.delivered;
	return FrameOutcome::kFrame;
}

// Waits for OpenNI2's next frame and copies it into buffer_ as the pending one.
Expected<FrameOutcome> OpenNi2Source::readFrame(std::chrono::nanoseconds timeout)
{
	openni::VideoStream *streams[] = {&state_->stream};
	int ready = -1;
	const auto ms = std::chrono::ceil<std::chrono::milliseconds>(timeout).count();
	const openni::Status waited = openni::OpenNI::waitForAnyStream(
		streams, 1, &ready, static_cast<int>(std::max<int64_t>(ms, 0)));
	if (waited == openni::STATUS_TIME_OUT) {
		++counters_.timeouts;
		return FrameOutcome::kTimeout;
	}
	if (waited != openni::STATUS_OK)
		return makeError(Errc::kIo, info_.uri + ": " + oniError("waiting for a depth frame failed (device removed?)"));

	openni::VideoFrameRef ref;
	if (state_->stream.readFrame(&ref) != openni::STATUS_OK || !ref.isValid())
		return makeError(Errc::kIo, info_.uri + ": " + oniError("reading a depth frame failed (device removed?)"));
	const auto index = static_cast<uint64_t>(ref.getFrameIndex());
	// The player rewound (repeat is on, see open()): a frame went missing
	// and the pass is over.
	if (state_->isFile && lastIndex_ && index <= *lastIndex_) {
		fileFramesRead_ = fileFrames_;
		return FrameOutcome::kEndOfStream;
	}
	const int w = buffer_.width(), h = buffer_.height();
	if (ref.getWidth() != w || ref.getHeight() != h)
		return makeError(Errc::kUnsupported, info_.uri + ": frame size changed while streaming");
	const int stride = ref.getStrideInBytes();
	const auto *bytes = static_cast<const uint8_t *>(ref.getData());
	if (stride < w * 2 || ref.getDataSize() < stride * (h - 1) + w * 2)
		return makeError(Errc::kCorrupt, info_.uri + ": frame data is smaller than its size says");
	for (int y = 0; y < h; ++y)
		std::memcpy(buffer_.view().row(y), bytes + static_cast<size_t>(y) * stride, w * 2);
	pendingIndex_ = index;
	pendingDeviceNs_ = static_cast<int64_t>(ref.getTimestamp()) * 1000;
	// A .oni keeps no host time: its device time stands for the recording's,
	// as a .rec's recorded host time does (ihf run paces and drops by it).
	pendingHostNs_ = state_->isFile ? pendingDeviceNs_ : clock_->nowNs();
	pending_ = true;
	++fileFramesRead_;
	return FrameOutcome::kFrame;
}

} // namespace ihf
