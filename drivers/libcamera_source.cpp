// SPDX-License-Identifier: MIT
#include "drivers/libcamera_source.h"

#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <mutex>

#include <sys/mman.h>

#include <libcamera/libcamera.h>

#include "drivers/clock.h"

namespace ihf {

namespace lc = libcamera;

namespace {

// Raw formats whose samples are stored as unpacked 16-bit little-endian words.
const lc::PixelFormat kSixteenBit[] = {
	lc::formats::R12, lc::formats::R10, lc::formats::SBGGR16, lc::formats::SGBRG16,
	lc::formats::SGRBG16, lc::formats::SRGGB16, lc::formats::SBGGR12, lc::formats::SGBRG12,
	lc::formats::SGRBG12, lc::formats::SRGGB12, lc::formats::SBGGR10, lc::formats::SGBRG10,
	lc::formats::SGRBG10, lc::formats::SRGGB10,
};

bool isSixteenBit(const lc::PixelFormat &f)
{
	for (const lc::PixelFormat &k : kSixteenBit)
		if (k == f)
			return true;
	return false;
}

template<typename T>
bool parseNumber(std::string_view s, T &out)
{
	auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
	return ec == std::errc() && p == s.data() + s.size();
}

// libcamera logs INFO and WARN lines to stderr; only its errors matter
// here, unless LIBCAMERA_LOG_LEVELS asks for more.
void quietLogging()
{
	if (!std::getenv("LIBCAMERA_LOG_LEVELS"))
		lc::logSetLevel("*", "ERROR");
}

} // namespace

struct LibcameraSource::State {
	std::unique_ptr<lc::CameraManager> manager;
	std::shared_ptr<lc::Camera> camera;
	bool acquired = false;
	std::unique_ptr<lc::CameraConfiguration> config;
	lc::Stream *stream = nullptr;
	unsigned int stride = 0;
	std::unique_ptr<lc::FrameBufferAllocator> allocator;
	std::vector<std::unique_ptr<lc::Request>> requests;
	struct Mapping {
		void *base = nullptr;
		size_t length = 0;
		const uint8_t *data = nullptr;
	};
	std::vector<Mapping> mappings; // per request, its buffer's first plane
	bool started = false;
	lc::Request *held = nullptr;

	// Completed requests arrive on libcamera's thread.
	std::mutex mutex;
	std::condition_variable ready;
	std::deque<lc::Request *> completed;
	bool removed = false;

	void onComplete(lc::Request *r)
	{
		std::lock_guard<std::mutex> lock(mutex);
		completed.push_back(r);
		ready.notify_one();
	}
	void onRemoved(std::shared_ptr<lc::Camera> cam)
	{
		std::lock_guard<std::mutex> lock(mutex);
		if (cam == camera) {
			removed = true;
			ready.notify_one();
		}
	}
};

Expected<LibcameraUri> parseLibcameraUri(const std::string &rest)
{
	LibcameraUri u;
	const size_t q = rest.find('?');
	u.cameraId = rest.substr(0, q);
	const std::string uri = "libcamera:" + rest;
	if (q == std::string::npos)
		return u;
	LibcameraSourceOptions &o = u.options;
	double fx = 0, fy = 0, cx = 0, cy = 0;
	int given = 0;
	std::string_view query(rest);
	query.remove_prefix(q + 1);
	while (!query.empty()) {
		const size_t amp = query.find('&');
		const std::string_view item = query.substr(0, amp);
		query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
		const size_t eq = item.find('=');
		const std::string key(item.substr(0, eq));
		const std::string_view v = eq == std::string_view::npos ? std::string_view() : item.substr(eq + 1);
		bool ok = eq != std::string_view::npos;
		if (!ok) {
		} else if (key == "width") {
			ok = parseNumber(v, o.width) && o.width > 0;
		} else if (key == "height") {
			ok = parseNumber(v, o.height) && o.height > 0;
		} else if (key == "buffers") {
			ok = parseNumber(v, o.buffers) && o.buffers >= 2 && o.buffers <= 32;
		} else if (key == "scale") {
			ok = parseNumber(v, o.scale) && o.scale > 0 && std::isfinite(o.scale);
		} else if (key == "hfov") {
			ok = parseNumber(v, o.hfovDeg) && o.hfovDeg > 0 && o.hfovDeg < 180;
		} else if (key == "fx" || key == "fy" || key == "cx" || key == "cy") {
			double &d = key == "fx" ? fx : key == "fy" ? fy : key == "cx" ? cx : cy;
			ok = parseNumber(v, d) && std::isfinite(d);
			++given;
		} else {
			return makeError(Errc::kInvalidArgument,
					 uri + ": unknown key '" + key +
						 "' (width, height, buffers, scale, hfov, fx, fy, cx, cy)");
		}
		if (!ok)
			return makeError(Errc::kInvalidArgument, uri + ": bad value for '" + key + "'");
	}
	if (given != 0 && given != 4)
		return makeError(Errc::kInvalidArgument, uri + ": give all of fx, fy, cx, cy or none");
	if (given == 4) {
		if (!(fx > 0 && fy > 0))
			return makeError(Errc::kInvalidArgument, uri + ": fx and fy must be > 0");
		CameraIntrinsics k;
		k.fx = fx, k.fy = fy, k.cx = cx, k.cy = cy;
		o.intrinsics = k;
	}
	return u;
}

Expected<std::vector<std::string>> listLibcameraCameras()
{
	quietLogging();
	lc::CameraManager manager;
	if (int r = manager.start(); r != 0)
		return makeError(Errc::kIo, std::string("libcamera: the camera manager did not start: ") +
						    std::strerror(-r));
	std::vector<std::string> ids;
	for (const auto &c : manager.cameras())
		ids.push_back(c->id());
	manager.stop();
	return ids;
}

LibcameraSource::LibcameraSource(std::string cameraId, LibcameraSourceOptions options, std::string uri)
	: cameraId_(std::move(cameraId)), options_(std::move(options))
{
	info_.uri = uri.empty() ? "libcamera:" + cameraId_ : std::move(uri);
	info_.live = true;
}

LibcameraSource::~LibcameraSource()
{
	close();
}

void LibcameraSource::close()
{
	if (!state_)
		return;
	stop();
	if (state_->camera) {
		state_->config.reset();
		if (state_->acquired)
			state_->camera->release();
		state_->camera.reset();
	}
	if (state_->manager) {
		state_->manager->cameraRemoved.disconnect(state_.get());
		state_->manager->stop();
	}
	state_.reset();
}

Status LibcameraSource::open()
{
	close();
	counters_ = {};
	lastIndex_.reset();
	state_ = std::make_unique<State>();
	State &s = *state_;
	auto fail = [this](Errc code, const std::string &what) -> Status {
		Error e = makeError(code, info_.uri + ": " + what);
		close();
		return e;
	};

	quietLogging();
	s.manager = std::make_unique<lc::CameraManager>();
	if (int r = s.manager->start(); r != 0)
		return fail(Errc::kIo, std::string("libcamera's camera manager did not start: ") + std::strerror(-r));
	const auto cameras = s.manager->cameras();
	if (cameras.empty())
		return fail(Errc::kNotFound, "no camera found (libcamera " + lc::CameraManager::version() +
						     " sees none: no sensor connected, or no pipeline handler for it)");
	if (cameraId_.empty()) {
		s.camera = cameras.front();
	} else {
		s.camera = s.manager->get(cameraId_);
		if (!s.camera) {
			std::string ids;
			for (const auto &c : cameras)
				ids += (ids.empty() ? "" : ", ") + c->id();
			return fail(Errc::kNotFound, "no camera with id '" + cameraId_ + "' (cameras: " + ids + ")");
		}
	}
	s.manager->cameraRemoved.connect(&s, &State::onRemoved);
	if (int r = s.camera->acquire(); r != 0)
		return fail(Errc::kIo, "camera " + s.camera->id() + " cannot be acquired: " + std::strerror(-r));
	s.acquired = true;

	s.config = s.camera->generateConfiguration({lc::StreamRole::Raw});
	if (!s.config || s.config->empty())
		return fail(Errc::kUnsupported, "camera " + s.camera->id() + " has no raw stream");
	lc::StreamConfiguration &sc = s.config->at(0);
	lc::PixelFormat chosen;
	std::string offered;
	for (const lc::PixelFormat &f : sc.formats().pixelformats()) {
		offered += (offered.empty() ? "" : ", ") + f.toString();
		if (!chosen.isValid() && isSixteenBit(f))
			chosen = f;
	}
	if (!chosen.isValid())
		return fail(Errc::kUnsupported, "camera " + s.camera->id() +
							" has no raw format with 16-bit samples (offers: " + offered + ")");
	sc.pixelFormat = chosen;
	if (options_.width && options_.height)
		sc.size = lc::Size(options_.width, options_.height);
	sc.bufferCount = options_.buffers;
	if (s.config->validate() == lc::CameraConfiguration::Invalid)
		return fail(Errc::kUnsupported, "camera " + s.camera->id() + " refused " + sc.toString());
	if (!isSixteenBit(sc.pixelFormat) ||
	    (options_.width && static_cast<int>(sc.size.width) != options_.width) ||
	    (options_.height && static_cast<int>(sc.size.height) != options_.height))
		return fail(Errc::kUnsupported, "camera " + s.camera->id() + " adjusted the stream to " + sc.toString());
	if (int r = s.camera->configure(s.config.get()); r != 0)
		return fail(Errc::kIo, "camera " + s.camera->id() + " cannot be configured: " + std::strerror(-r));
	s.stream = sc.stream();
	s.stride = sc.stride;
	if (s.stride < sc.size.width * 2 || s.stride % 2)
		return fail(Errc::kUnsupported, "camera " + s.camera->id() + " reports an unusable stride");

	const int w = static_cast<int>(sc.size.width), h = static_cast<int>(sc.size.height);
	if (options_.intrinsics) {
		info_.intrinsics = *options_.intrinsics;
	} else {
		const double f = w / (2.0 * std::tan(options_.hfovDeg * M_PI / 360.0));
		info_.intrinsics.fx = info_.intrinsics.fy = f;
		info_.intrinsics.cx = (w - 1) / 2.0;
		info_.intrinsics.cy = (h - 1) / 2.0;
	}
	info_.intrinsics.width = w;
	info_.intrinsics.height = h;
	info_.depthScale = options_.scale;
	info_.sensorId = "libcamera " + s.camera->id() + " (" + sc.toString() + ")";
	return {};
}

Status LibcameraSource::start()
{
	if (!state_ || !state_->stream)
		return makeError(Errc::kInvalidArgument, info_.uri + ": start() before open()");
	stop();
	State &s = *state_;
	s.allocator = std::make_unique<lc::FrameBufferAllocator>(s.camera);
	if (s.allocator->allocate(s.stream) < 0)
		return makeError(Errc::kIo, info_.uri + ": cannot allocate frame buffers");
	const size_t need = static_cast<size_t>(s.stride) * (info_.intrinsics.height - 1) + info_.intrinsics.width * 2;
	for (const std::unique_ptr<lc::FrameBuffer> &buffer : s.allocator->buffers(s.stream)) {
		const lc::FrameBuffer::Plane &plane = buffer->planes().front();
		const size_t length = static_cast<size_t>(plane.offset) + plane.length;
		void *base = mmap(nullptr, length, PROT_READ, MAP_SHARED, plane.fd.get(), 0);
		if (base == MAP_FAILED || plane.length < need) {
			if (base != MAP_FAILED)
				munmap(base, length);
			stop();
			return makeError(Errc::kIo, info_.uri + ": cannot map a frame buffer");
		}
		std::unique_ptr<lc::Request> request = s.camera->createRequest(s.requests.size());
		if (!request || request->addBuffer(s.stream, buffer.get()) != 0) {
			munmap(base, length);
			stop();
			return makeError(Errc::kIo, info_.uri + ": cannot create a capture request");
		}
		s.mappings.push_back({base, length, static_cast<const uint8_t *>(base) + plane.offset});
		s.requests.push_back(std::move(request));
	}
	s.camera->requestCompleted.connect(&s, &State::onComplete);
	if (int r = s.camera->start(); r != 0) {
		stop();
		return makeError(Errc::kIo, info_.uri + ": camera did not start: " + std::strerror(-r));
	}
	s.started = true;
	for (auto &r : s.requests)
		if (s.camera->queueRequest(r.get()) != 0) {
			stop();
			return makeError(Errc::kIo, info_.uri + ": cannot queue a capture request");
		}
	return {};
}

void LibcameraSource::stop()
{
	if (!state_)
		return;
	State &s = *state_;
	if (s.started)
		s.camera->stop();
	s.started = false;
	if (s.camera)
		s.camera->requestCompleted.disconnect(&s);
	s.held = nullptr;
	{
		std::lock_guard<std::mutex> lock(s.mutex);
		s.completed.clear();
	}
	s.requests.clear();
	for (const State::Mapping &m : s.mappings)
		munmap(m.base, m.length);
	s.mappings.clear();
	if (s.allocator && s.stream)
		s.allocator->free(s.stream);
	s.allocator.reset();
}

Expected<FrameOutcome> LibcameraSource::next(Frame &frame, std::chrono::nanoseconds timeout)
{
	if (!state_ || !state_->started)
		return makeError(Errc::kInvalidArgument, info_.uri + ": next() before start()");
	State &s = *state_;
	auto requeue = [&](lc::Request *r) -> bool {
		r->reuse(lc::Request::ReuseBuffers);
		return s.camera->queueRequest(r) == 0;
	};
	if (s.held) {
		lc::Request *r = s.held;
		s.held = nullptr;
		if (!requeue(r))
			return makeError(Errc::kIo, info_.uri + ": cannot queue a capture request again");
	}
	const auto deadline = std::chrono::steady_clock::now() + timeout;
	for (;;) {
		lc::Request *r = nullptr;
		{
			std::unique_lock<std::mutex> lock(s.mutex);
			s.ready.wait_until(lock, deadline, [&] { return s.removed || !s.completed.empty(); });
			if (s.removed)
				return makeError(Errc::kIo, info_.uri + ": camera " + s.camera->id() +
								    " was removed; reopen when it is back");
			if (s.completed.empty()) {
				++counters_.timeouts;
				return FrameOutcome::kTimeout;
			}
			r = s.completed.front();
			s.completed.pop_front();
		}
		const lc::FrameBuffer *buffer = r->findBuffer(s.stream);
		const bool bad = r->status() != lc::Request::RequestComplete || !buffer ||
				 buffer->metadata().status != lc::FrameMetadata::FrameSuccess;
		if (bad) {
			++counters_.corrupt;
			if (buffer)
				lastIndex_ = buffer->metadata().sequence; // not a gap as well
			if (r->status() == lc::Request::RequestCancelled)
				return makeError(Errc::kIo, info_.uri + ": capture was cancelled (camera stopped?)");
			if (!requeue(r))
				return makeError(Errc::kIo, info_.uri + ": cannot queue a capture request again");
			continue;
		}
		const lc::FrameMetadata &md = buffer->metadata();
		SteadyPacingClock clock;
		frame.index = md.sequence;
		frame.deviceTimestampNs = static_cast<int64_t>(md.timestamp);
		// libcamera stamps with CLOCK_MONOTONIC (the steady clock) where it can.
		frame.hostTimestampNs = md.timestamp ? static_cast<int64_t>(md.timestamp) : clock.nowNs();
		frame.intrinsics = info_.intrinsics;
		frame.depthScale = info_.depthScale;
		frame.depth = ImageView<const uint16_t>(
			reinterpret_cast<const uint16_t *>(s.mappings[r->cookie()].data), info_.intrinsics.width,
			info_.intrinsics.height, static_cast<int>(s.stride / 2));
		s.held = r;
		if (lastIndex_ && frame.index > *lastIndex_ + 1)
			counters_.dropped += frame.index - *lastIndex_ - 1;
		lastIndex_ = frame.index;
		++counters_.delivered;
		return FrameOutcome::kFrame;
	}
}

} // namespace ihf
