// SPDX-License-Identifier: MIT
#pragma once

// USB depth sensors ihf knows by vendor/product id, in one table
// (usb_sensor_ids.cpp): PrimeSense / ASUS Xtion, Microsoft Kinect v1, v2
// and Azure Kinect, Orbbec, Intel RealSense. An entry may cover a whole
// vendor (Orbbec's products are many); Intel's vendor id is shared with
// every Intel USB part, so RealSense products are listed one by one.

#include <cstdint>
#include <span>

namespace ihf {

struct UsbSensorModel {
	uint16_t vendor = 0;
	uint16_t product = 0;
	bool anyProduct = false; // matches every product of the vendor
	const char *family = ""; // "PrimeSense", "Kinect v1", ...
	const char *model = "";
	const char *sourceHint = ""; // the frame source URI that reads it
};

std::span<const UsbSensorModel> knownUsbSensors();

// The entry for vendor:product, an exact entry before a vendor-wide one;
// nullptr for anything else.
const UsbSensorModel *matchUsbSensor(uint16_t vendor, uint16_t product);

} // namespace ihf
