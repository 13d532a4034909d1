// SPDX-License-Identifier: MIT
// An OpenNI2 driver plugin (libihfrecdriver.so.0) that exposes an ihf .rec
// recording as a depth device, so the real libOpenNI2 (device open, streams,
// openni::Recorder, .oni playback) can be exercised without hardware.
//
// URI: "ihfrec:PATH". OpenNI2 asks every driver to try an unknown URI; this
// one accepts the scheme, announces the device and, once its depth stream is
// started, emits the recording's frames (skipping corrupt ones, as a device
// would lose them) every framePeriod, with the recorded frame index and
// device timestamp. It reports the stream properties OpenNI2's recorder and
// file player need: VIDEO_MODE, CROPPING, STRIDE, the fields of view, and
// the value range.

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

// ONI_EXPORT_DRIVER uses OpenNI's allocation macros, which live in headers
// libopenni2-dev does not ship.
#define XN_NEW(type, ...) new type(__VA_ARGS__)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

#include "drivers/recording_reader.h"

namespace {

constexpr const char *kScheme = "ihfrec:";
constexpr auto kFramePeriod = std::chrono::milliseconds(10);
// Before the first frame: time for a recorder started just before the
// stream to get going (openni::Recorder starts asynchronously).
constexpr auto kPreRoll = std::chrono::milliseconds(100);

using ihf::RecordingReader;

// Copies a property value out if the caller's buffer has the right size.
template<typename T>
OniStatus putProperty(const T &value, void *data, int *size)
{
	if (*size != static_cast<int>(sizeof(T)))
		return ONI_STATUS_BAD_PARAMETER;
	std::memcpy(data, &value, sizeof(T));
	return ONI_STATUS_OK;
}

OniVideoMode videoModeOf(const ihf::recording::RecordingHeader &h)
{
	OniVideoMode m{};
	// OpenNI2 knows 1 mm and 100 um depth; other scales go out as 1 mm.
	m.pixelFormat = std::abs(h.depthScale - 0.1) < 1e-9 ? ONI_PIXEL_FORMAT_DEPTH_100_UM
							     : ONI_PIXEL_FORMAT_DEPTH_1_MM;
	m.resolutionX = h.intrinsics.width;
	m.resolutionY = h.intrinsics.height;
	m.fps = 30;
	return m;
}

class RecDepthStream : public oni::driver::StreamBase
{
public:
	explicit RecDepthStream(RecordingReader reader)
		: reader_(std::move(reader)), mode_(videoModeOf(reader_.header())) {}
	~RecDepthStream() override { stop(); }

	OniStatus start() override
	{
		stop();
		running_ = true;
		thread_ = std::thread([this] { run(); });
		return ONI_STATUS_OK;
	}

	void stop() override
	{
		{
			std::lock_guard<std::mutex> lock(mutex_);
			running_ = false;
		}
		wake_.notify_all();
		if (thread_.joinable())
			thread_.join();
	}

	OniBool isPropertySupported(int id) override
	{
		switch (id) {
		case ONI_STREAM_PROPERTY_VIDEO_MODE:
		case ONI_STREAM_PROPERTY_CROPPING:
		case ONI_STREAM_PROPERTY_STRIDE:
		case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
		case ONI_STREAM_PROPERTY_VERTICAL_FOV:
		case ONI_STREAM_PROPERTY_MAX_VALUE:
		case ONI_STREAM_PROPERTY_MIN_VALUE:
		case ONI_STREAM_PROPERTY_MIRRORING:
			return TRUE;
		default:
			return FALSE;
		}
	}

	OniStatus getProperty(int id, void *data, int *size) override
	{
		const auto &k = reader_.header().intrinsics;
		switch (id) {
		case ONI_STREAM_PROPERTY_VIDEO_MODE:
			return putProperty(mode_, data, size);
		case ONI_STREAM_PROPERTY_CROPPING: {
			OniCropping c{};
			c.enabled = FALSE;
			c.width = k.width;
			c.height = k.height;
			return putProperty(c, data, size);
		}
		case ONI_STREAM_PROPERTY_STRIDE:
			return putProperty(static_cast<int>(k.width * sizeof(uint16_t)), data, size);
		case ONI_STREAM_PROPERTY_HORIZONTAL_FOV:
			return putProperty(static_cast<float>(2 * std::atan(k.width / (2 * k.fx))), data, size);
		case ONI_STREAM_PROPERTY_VERTICAL_FOV:
			return putProperty(static_cast<float>(2 * std::atan(k.height / (2 * k.fy))), data, size);
		case ONI_STREAM_PROPERTY_MAX_VALUE:
			return putProperty(static_cast<int>(0xffff), data, size);
		case ONI_STREAM_PROPERTY_MIN_VALUE:
			return putProperty(0, data, size);
		case ONI_STREAM_PROPERTY_MIRRORING:
			return putProperty(static_cast<OniBool>(FALSE), data, size);
		default:
			return ONI_STATUS_NOT_SUPPORTED;
		}
	}

	OniStatus setProperty(int id, const void *data, int size) override
	{
		// The one mode there is may be set again; nothing else changes.
		if (id == ONI_STREAM_PROPERTY_VIDEO_MODE && size == sizeof(OniVideoMode) &&
		    std::memcmp(data, &mode_, sizeof(mode_)) == 0)
			return ONI_STATUS_OK;
		if (id == ONI_STREAM_PROPERTY_MIRRORING && size == sizeof(OniBool) &&
		    *static_cast<const OniBool *>(data) == FALSE)
			return ONI_STATUS_OK;
		return ONI_STATUS_NOT_SUPPORTED;
	}

private:
	void run()
	{
		const auto &k = reader_.header().intrinsics;
		ihf::Image<uint16_t> depth(k.width, k.height);
		const int bytes = k.width * k.height * 2;
		for (size_t i = 0; i < reader_.frameCount(); ++i) {
			{
				std::unique_lock<std::mutex> lock(mutex_);
				if (wake_.wait_for(lock, i == 0 ? kPreRoll : kFramePeriod,
						   [this] { return !running_; }))
					return;
			}
			ihf::recording::FrameRecord rec;
			auto check = reader_.read(i, rec, depth.view());
			if (!check || *check != ihf::FrameCheck::kOk)
				continue;
			OniFrame *f = getServices().acquireFrame();
			if (!f)
				continue;
			std::memcpy(f->data, depth.data(), bytes);
			f->dataSize = bytes;
			f->sensorType = ONI_SENSOR_DEPTH;
			f->frameIndex = static_cast<int>(rec.index);
			f->timestamp = static_cast<uint64_t>(rec.deviceTimestampNs / 1000);
			f->videoMode = mode_;
			f->width = k.width;
			f->height = k.height;
			f->croppingEnabled = FALSE;
			f->cropOriginX = 0;
			f->cropOriginY = 0;
			f->stride = k.width * 2;
			raiseNewFrame(f);
			getServices().releaseFrame(f);
		}
	}

	RecordingReader reader_;
	OniVideoMode mode_;
	std::thread thread_;
	std::mutex mutex_;
	std::condition_variable wake_;
	bool running_ = false;
};

class RecDevice : public oni::driver::DeviceBase
{
public:
	RecDevice(std::string path, RecordingReader reader)
		: path_(std::move(path)), mode_(videoModeOf(reader.header()))
	{
		sensor_.sensorType = ONI_SENSOR_DEPTH;
		sensor_.numSupportedVideoModes = 1;
		sensor_.pSupportedVideoModes = &mode_;
	}

	OniStatus getSensorInfoList(OniSensorInfo **infos, int *count) override
	{
		*infos = &sensor_;
		*count = 1;
		return ONI_STATUS_OK;
	}

	oni::driver::StreamBase *createStream(OniSensorType type) override
	{
		if (type != ONI_SENSOR_DEPTH)
			return nullptr;
		auto reader = RecordingReader::open(path_);
		if (!reader)
			return nullptr;
		return new RecDepthStream(std::move(*reader));
	}

	void destroyStream(oni::driver::StreamBase *stream) override { delete stream; }

private:
	std::string path_;
	OniVideoMode mode_;
	OniSensorInfo sensor_{};
};

class RecDriver : public oni::driver::DriverBase
{
public:
	explicit RecDriver(OniDriverServices *services) : DriverBase(services) {}

	OniStatus tryDevice(const char *uri) override
	{
		if (!uri || std::strncmp(uri, kScheme, std::strlen(kScheme)) != 0)
			return ONI_STATUS_ERROR;
		auto reader = RecordingReader::open(uri + std::strlen(kScheme));
		if (!reader) {
			getServices().errorLoggerAppend("ihfrec: %s", reader.error().message.c_str());
			return ONI_STATUS_ERROR;
		}
		auto info = std::make_unique<OniDeviceInfo>();
		std::memset(info.get(), 0, sizeof(OniDeviceInfo));
		std::strncpy(info->uri, uri, ONI_MAX_STR - 1);
		std::strncpy(info->vendor, "ihf", ONI_MAX_STR - 1);
		std::strncpy(info->name, "recording", ONI_MAX_STR - 1);
		deviceConnected(info.get());
		infos_.push_back(std::move(info));
		return ONI_STATUS_OK;
	}

	oni::driver::DeviceBase *deviceOpen(const char *uri, const char * /*mode*/) override
	{
		if (!uri || std::strncmp(uri, kScheme, std::strlen(kScheme)) != 0)
			return nullptr;
		const std::string path = uri + std::strlen(kScheme);
		auto reader = RecordingReader::open(path);
		if (!reader) {
			getServices().errorLoggerAppend("ihfrec: %s", reader.error().message.c_str());
			return nullptr;
		}
		return new RecDevice(path, std::move(*reader));
	}

	void deviceClose(oni::driver::DeviceBase *device) override { delete device; }

	void shutdown() override {}

private:
	std::vector<std::unique_ptr<OniDeviceInfo>> infos_;
};

} // namespace

ONI_EXPORT_DRIVER(RecDriver)
