// SPDX-License-Identifier: MIT
#include "drivers/usb_sensor_ids.h"

namespace ihf {

namespace {

// Sources: the product lists of OpenNI2's PS1080 driver (PrimeSense, Orbbec),
// libfreenect (Kinect v1), libfreenect2 (Kinect v2), the Azure Kinect SDK and
// librealsense (RealSense).
constexpr UsbSensorModel kSensors[] = {
	{0x1d27, 0x0500, false, "PrimeSense", "PrimeSense PS1080 (SDK 5.0)", "openni2:"},
	{0x1d27, 0x0600, false, "PrimeSense", "PrimeSense Carmine 1.08 / ASUS Xtion PRO", "openni2:"},
	{0x1d27, 0x0601, false, "PrimeSense", "ASUS Xtion PRO LIVE / PrimeSense Carmine", "openni2:"},
	{0x1d27, 0x0609, false, "PrimeSense", "PrimeSense Carmine 1.09", "openni2:"},
	{0x045e, 0x02ae, false, "Kinect v1", "Microsoft Kinect for Xbox 360 (camera)", "openni2:"},
	{0x045e, 0x02bf, false, "Kinect v1", "Microsoft Kinect for Windows (camera)", "openni2:"},
	{0x045e, 0x02c4, false, "Kinect v2", "Microsoft Kinect v2 (preview)", "openni2:"},
	{0x045e, 0x02d8, false, "Kinect v2", "Microsoft Kinect v2", "openni2:"},
	{0x045e, 0x097c, false, "Azure Kinect", "Microsoft Azure Kinect DK (depth)", "v4l2:"},
	{0x2bc5, 0x0401, false, "Orbbec", "Orbbec Astra", "openni2:"},
	{0x2bc5, 0x0402, false, "Orbbec", "Orbbec Astra S", "openni2:"},
	{0x2bc5, 0x0403, false, "Orbbec", "Orbbec Astra Pro", "openni2:"},
	{0x2bc5, 0x0404, false, "Orbbec", "Orbbec Astra Mini", "openni2:"},
	{0x2bc5, 0x0407, false, "Orbbec", "Orbbec Astra Mini S", "openni2:"},
	{0x2bc5, 0x0000, true, "Orbbec", "Orbbec depth camera", "v4l2:"},
	{0x8086, 0x0aa5, false, "RealSense", "Intel RealSense SR300", "v4l2:"},
	{0x8086, 0x0ad1, false, "RealSense", "Intel RealSense D400", "v4l2:"},
	{0x8086, 0x0ad2, false, "RealSense", "Intel RealSense D410", "v4l2:"},
	{0x8086, 0x0ad3, false, "RealSense", "Intel RealSense D415", "v4l2:"},
	{0x8086, 0x0ad4, false, "RealSense", "Intel RealSense D430", "v4l2:"},
	{0x8086, 0x0b07, false, "RealSense", "Intel RealSense D435", "v4l2:"},
	{0x8086, 0x0b3a, false, "RealSense", "Intel RealSense D435i", "v4l2:"},
	{0x8086, 0x0b5b, false, "RealSense", "Intel RealSense D405", "v4l2:"},
	{0x8086, 0x0b5c, false, "RealSense", "Intel RealSense D455", "v4l2:"},
	{0x8086, 0x0b64, false, "RealSense", "Intel RealSense L515", "v4l2:"},
};

} // namespace

std::span<const UsbSensorModel> knownUsbSensors() { return kSensors; }

const UsbSensorModel *matchUsbSensor(uint16_t vendor, uint16_t product)
{
	const UsbSensorModel *wide = nullptr;
	for (const UsbSensorModel &m : kSensors) {
		if (m.vendor != vendor)
			continue;
		if (!m.anyProduct && m.product == product)
			return &m;
		if (m.anyProduct && !wide)
			wide = &m;
	}
	return wide;
}

} // namespace ihf
