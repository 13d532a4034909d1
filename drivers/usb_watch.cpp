// SPDX-License-Identifier: MIT
#include "drivers/usb_watch.h"

#include <algorithm>
#include <cstdio>
#include <thread>

#include <libusb.h>

namespace ihf {

namespace {

int onHotplug(libusb_context *, libusb_device *, libusb_hotplug_event, void *self)
{
	static_cast<LibusbEnumerator *>(self)->markChanged();
	return 0; // stay registered
}

} // namespace

std::string UsbSensor::describe() const
{
	char buf[48];
	std::snprintf(buf, sizeof(buf), "%04x:%04x at %s", device.vendor, device.product, device.port.c_str());
	return buf;
}

bool UsbSensor::operator==(const UsbSensor &o) const
{
	return device.vendor == o.device.vendor && device.product == o.device.product &&
	       device.bus == o.device.bus && device.port == o.device.port;
}

Expected<UsbSensorFilter> parseUsbSensorFilter(const std::string &text)
{
	if (text.empty() || text == "any")
		return UsbSensorFilter{};
	unsigned v = 0, p = 0;
	char extra = 0;
	if (text.size() != 9 || std::sscanf(text.c_str(), "%4x:%4x%c", &v, &p, &extra) != 2)
		return makeError(Errc::kInvalidArgument, "USB sensor '" + text + "': expected VID:PID in hex (e.g. 045e:02d8) or any");
	return UsbSensorFilter{static_cast<uint16_t>(v), static_cast<uint16_t>(p)};
}

Expected<std::unique_ptr<LibusbEnumerator>> LibusbEnumerator::create()
{
	std::unique_ptr<LibusbEnumerator> e(new LibusbEnumerator());
	const int r = libusb_init(&e->ctx_);
	if (r != 0) {
		e->ctx_ = nullptr;
		return makeError(Errc::kIo, std::string("libusb: cannot initialise: ") + libusb_strerror(r));
	}
	if (libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
		// One callback per known vendor: any arrival or departure marks the list stale.
		std::vector<uint16_t> vendors;
		for (const UsbSensorModel &m : knownUsbSensors())
			if (std::find(vendors.begin(), vendors.end(), m.vendor) == vendors.end())
				vendors.push_back(m.vendor);
		bool ok = true;
		for (uint16_t v : vendors) {
			libusb_hotplug_callback_handle h;
			const int rc = libusb_hotplug_register_callback(
				e->ctx_,
				static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
								  LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
				LIBUSB_HOTPLUG_NO_FLAGS, v, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
				&onHotplug, e.get(), &h);
			if (rc != LIBUSB_SUCCESS) {
				ok = false;
				break;
			}
			e->callbacks_.push_back(h);
		}
		e->hotplug_ = ok;
	}
	return e;
}

LibusbEnumerator::~LibusbEnumerator()
{
	if (!ctx_)
		return;
	for (int h : callbacks_)
		libusb_hotplug_deregister_callback(ctx_, h);
	libusb_exit(ctx_);
}

bool LibusbEnumerator::waitForChange(std::chrono::milliseconds timeout)
{
	if (!hotplug_) {
		std::this_thread::sleep_for(timeout);
		return true; // periodic enumeration
	}
	if (!changed_) {
		timeval tv{static_cast<time_t>(timeout.count() / 1000),
			   static_cast<suseconds_t>((timeout.count() % 1000) * 1000)};
		libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
	}
	const bool changed = changed_;
	changed_ = false;
	return changed;
}

Expected<std::vector<UsbDeviceEntry>> LibusbEnumerator::list()
{
	libusb_device **devices = nullptr;
	const ssize_t n = libusb_get_device_list(ctx_, &devices);
	if (n < 0)
		return makeError(Errc::kIo, std::string("libusb: cannot list devices: ") +
						    libusb_strerror(static_cast<int>(n)));
	std::vector<UsbDeviceEntry> out;
	for (ssize_t i = 0; i < n; ++i) {
		libusb_device_descriptor d{};
		if (libusb_get_device_descriptor(devices[i], &d) != 0)
			continue;
		UsbDeviceEntry e;
		e.vendor = d.idVendor;
		e.product = d.idProduct;
		e.bus = libusb_get_bus_number(devices[i]);
		uint8_t ports[8];
		const int np = libusb_get_port_numbers(devices[i], ports, 8);
		e.port = std::to_string(e.bus);
		for (int k = 0; k < np; ++k) {
			e.port += k == 0 ? '-' : '.';
			e.port += std::to_string(ports[k]);
		}
		out.push_back(std::move(e));
	}
	libusb_free_device_list(devices, 1);
	return out;
}

Expected<std::vector<UsbSensor>> findUsbSensors(UsbEnumerator &enumerator, UsbSensorFilter filter)
{
	Expected<std::vector<UsbDeviceEntry>> devices = enumerator.list();
	if (!devices)
		return devices.error();
	std::vector<UsbSensor> out;
	for (const UsbDeviceEntry &d : *devices) {
		UsbSensor s{d, matchUsbSensor(d.vendor, d.product)};
		if (s.model && filter.matches(s))
			out.push_back(std::move(s));
	}
	return out;
}

UsbSensorWatch::UsbSensorWatch(UsbEnumerator &enumerator, UsbSensorFilter filter)
	: enumerator_(enumerator), filter_(filter)
{
}

Expected<std::vector<UsbSensorEvent>> UsbSensorWatch::poll()
{
	Expected<std::vector<UsbSensor>> now = findUsbSensors(enumerator_, filter_);
	if (!now)
		return now.error();
	std::vector<UsbSensorEvent> events;
	for (const UsbSensor &old : present_)
		if (std::find(now->begin(), now->end(), old) == now->end())
			events.push_back({false, old});
	for (const UsbSensor &s : *now)
		if (std::find(present_.begin(), present_.end(), s) == present_.end())
			events.push_back({true, s});
	present_ = std::move(*now);
	return events;
}

} // namespace ihf
