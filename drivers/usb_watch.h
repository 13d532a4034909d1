// SPDX-License-Identifier: MIT
#pragma once

// Which known USB depth sensors are plugged in, and when that changes.
// UsbEnumerator lists the USB devices present (LibusbEnumerator: the real
// bus through libusb; tests inject their own list). UsbSensorWatch keeps the
// known sensors seen last time and reports the ones that arrived or left.
// LibusbEnumerator::waitForChange() sleeps in libusb's hotplug events where
// the platform has them (a callback marks the list stale), or for the whole
// interval otherwise (periodic enumeration).

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/common/expected.h"
#include "drivers/usb_sensor_ids.h"

struct libusb_context;
struct libusb_device;

namespace ihf {

struct UsbDeviceEntry {
	uint16_t vendor = 0;
	uint16_t product = 0;
	uint8_t bus = 0;
	std::string port; // "1-2.3": bus and hub ports, stable while plugged in the same socket
};

class UsbEnumerator
{
public:
	virtual ~UsbEnumerator() = default;
	virtual Expected<std::vector<UsbDeviceEntry>> list() = 0;
	// Returns true when the device list may have changed (or the interval
	// passed without a way to know); false when nothing changed.
	virtual bool waitForChange(std::chrono::milliseconds timeout) = 0;
};

class LibusbEnumerator : public UsbEnumerator
{
public:
	static Expected<std::unique_ptr<LibusbEnumerator>> create();
	~LibusbEnumerator() override;

	Expected<std::vector<UsbDeviceEntry>> list() override;
	bool waitForChange(std::chrono::milliseconds timeout) override;
	bool hotplug() const { return hotplug_; }
	// Called from libusb's hotplug callback: the device list is stale.
	void markChanged() { changed_ = true; }

private:
	LibusbEnumerator() = default;

	libusb_context *ctx_ = nullptr;
	std::vector<int> callbacks_;
	bool hotplug_ = false;
	bool changed_ = true;
};

struct UsbSensor {
	UsbDeviceEntry device;
	const UsbSensorModel *model = nullptr;
	// "045e:02d8 at 1-2.3"
	std::string describe() const;
	bool operator==(const UsbSensor &o) const;
};

struct UsbSensorEvent {
	bool arrived = false; // false: left
	UsbSensor sensor;
};

// Only sensors of this vendor:product (0:0 = every known sensor).
struct UsbSensorFilter {
	uint16_t vendor = 0;
	uint16_t product = 0;
	bool matches(const UsbSensor &s) const
	{
		return (vendor == 0 && product == 0) ||
		       (s.device.vendor == vendor && s.device.product == product);
	}
};

// Parses "VID:PID" (hex) or "any".
Expected<UsbSensorFilter> parseUsbSensorFilter(const std::string &text);

// The known sensors among the enumerator's devices.
Expected<std::vector<UsbSensor>> findUsbSensors(UsbEnumerator &enumerator, UsbSensorFilter filter = {});

class UsbSensorWatch
{
public:
	explicit UsbSensorWatch(UsbEnumerator &enumerator, UsbSensorFilter filter = {});

	// Enumerates and compares with the previous call (the first call reports
	// every sensor present as arrived).
	Expected<std::vector<UsbSensorEvent>> poll();
	const std::vector<UsbSensor> &present() const { return present_; }
	UsbEnumerator &enumerator() { return enumerator_; }

private:
	UsbEnumerator &enumerator_;
	UsbSensorFilter filter_;
	std::vector<UsbSensor> present_;
};

} // namespace ihf
