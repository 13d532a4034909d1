// SPDX-License-Identifier: MIT
// USB depth sensors: the id table, the watch's arrival/departure logic over
// an injected device list, and the real libusb enumeration (which finds no
// sensor on this machine and must simply work).

#include <cstring>
#include <set>

#include <gtest/gtest.h>

#include "drivers/usb_watch.h"

namespace ihf {
namespace {

// The bus as a list the test edits.
class ListEnumerator : public UsbEnumerator
{
public:
	Expected<std::vector<UsbDeviceEntry>> list() override
	{
		++lists;
		if (fail)
			return makeError(Errc::kIo, "bus gone");
		return devices;
	}
	bool waitForChange(std::chrono::milliseconds) override { return true; }

	std::vector<UsbDeviceEntry> devices;
	bool fail = false;
	int lists = 0;
};

TEST(UsbSensorIds, KnownIdsMatchTheirModels)
{
	const UsbSensorModel *k2 = matchUsbSensor(0x045e, 0x02d8);
	ASSERT_NE(k2, nullptr);
	EXPECT_STREQ(k2->family, "Kinect v2");
	const UsbSensorModel *k1 = matchUsbSensor(0x045e, 0x02ae);
	ASSERT_NE(k1, nullptr);
	EXPECT_STREQ(k1->family, "Kinect v1");
	EXPECT_STREQ(matchUsbSensor(0x1d27, 0x0601)->family, "PrimeSense");
	EXPECT_STREQ(matchUsbSensor(0x8086, 0x0b07)->model, "Intel RealSense D435");
	// Orbbec: an exact entry wins over the vendor-wide one.
	EXPECT_STREQ(matchUsbSensor(0x2bc5, 0x0401)->model, "Orbbec Astra");
	const UsbSensorModel *orbbecOther = matchUsbSensor(0x2bc5, 0x0660);
	ASSERT_NE(orbbecOther, nullptr);
	EXPECT_TRUE(orbbecOther->anyProduct);
	// Not sensors: the Kinect's motor and audio, other Intel and Microsoft parts.
	EXPECT_EQ(matchUsbSensor(0x045e, 0x02b0), nullptr);
	EXPECT_EQ(matchUsbSensor(0x045e, 0x0745), nullptr);
	EXPECT_EQ(matchUsbSensor(0x8086, 0x0024), nullptr);
	EXPECT_EQ(matchUsbSensor(0x1d6b, 0x0002), nullptr); // a Linux root hub
}

TEST(UsbSensorIds, TableIsConsistent)
{
	std::set<std::pair<uint16_t, uint16_t>> exact;
	std::set<uint16_t> wide;
	for (const UsbSensorModel &m : knownUsbSensors()) {
		EXPECT_NE(m.vendor, 0);
		EXPECT_GT(std::strlen(m.family), 0u);
		EXPECT_GT(std::strlen(m.model), 0u);
		EXPECT_TRUE(std::string(m.sourceHint) == "openni2:" || std::string(m.sourceHint) == "v4l2:")
			<< m.model;
		if (m.anyProduct)
			EXPECT_TRUE(wide.insert(m.vendor).second) << "two vendor-wide entries for " << m.vendor;
		else
			EXPECT_TRUE(exact.insert({m.vendor, m.product}).second) << m.model;
		EXPECT_NE(m.vendor, 0x8086 * m.anyProduct) << "Intel's id is not only RealSense";
	}
	EXPECT_GE(exact.size(), 20u);
}

TEST(UsbSensorWatch, ReportsArrivalsAndDeparturesOfKnownSensorsOnly)
{
	ListEnumerator bus;
	bus.devices = {{0x1d6b, 0x0002, 1, "1"}, {0x045e, 0x02d8, 2, "2-1"}, {0x046d, 0xc52b, 1, "1-3"}};
	UsbSensorWatch watch(bus);
	auto e = watch.poll();
	ASSERT_TRUE(e.ok());
	ASSERT_EQ(e->size(), 1u);
	EXPECT_TRUE((*e)[0].arrived);
	EXPECT_EQ((*e)[0].sensor.describe(), "045e:02d8 at 2-1");
	EXPECT_STREQ((*e)[0].sensor.model->family, "Kinect v2");
	EXPECT_TRUE(watch.poll()->empty()); // nothing changed

	bus.devices.erase(bus.devices.begin() + 1); // unplugged
	e = watch.poll();
	ASSERT_EQ(e->size(), 1u);
	EXPECT_FALSE((*e)[0].arrived);
	EXPECT_TRUE(watch.present().empty());

	// Back in another socket, with an Xtion beside it.
	bus.devices.push_back({0x045e, 0x02d8, 3, "3-2"});
	bus.devices.push_back({0x1d27, 0x0601, 3, "3-1"});
	e = watch.poll();
	ASSERT_EQ(e->size(), 2u);
	EXPECT_TRUE((*e)[0].arrived && (*e)[1].arrived);
	EXPECT_EQ(watch.present().size(), 2u);

	// Moving sockets is a departure and an arrival.
	bus.devices.back().port = "3-4";
	e = watch.poll();
	ASSERT_EQ(e->size(), 2u);
	EXPECT_FALSE((*e)[0].arrived);
	EXPECT_TRUE((*e)[1].arrived);

	bus.fail = true;
	EXPECT_FALSE(watch.poll().ok());
}

TEST(UsbSensorWatch, FilterKeepsOneModel)
{
	auto f = parseUsbSensorFilter("1d27:0601");
	ASSERT_TRUE(f.ok());
	ListEnumerator bus;
	bus.devices = {{0x045e, 0x02d8, 2, "2-1"}, {0x1d27, 0x0601, 3, "3-1"}};
	UsbSensorWatch watch(bus, *f);
	auto e = watch.poll();
	ASSERT_EQ(e->size(), 1u);
	EXPECT_EQ((*e)[0].sensor.device.vendor, 0x1d27);
	EXPECT_TRUE(parseUsbSensorFilter("any").ok());
	EXPECT_FALSE(parseUsbSensorFilter("kinect").ok());
	EXPECT_FALSE(parseUsbSensorFilter("045e:02d8x").ok());
	EXPECT_FALSE(parseUsbSensorFilter("45e:2d8").ok());
}

TEST(LibusbEnumerator, RealBusEnumeratesWithoutFailing)
{
	auto e = LibusbEnumerator::create();
	ASSERT_TRUE(e.ok()) << e.error().message;
	auto devices = (*e)->list();
	ASSERT_TRUE(devices.ok()) << devices.error().message;
	auto sensors = findUsbSensors(**e);
	ASSERT_TRUE(sensors.ok());
	std::printf("libusb: %zu devices, %zu known depth sensors, hotplug %s\n", devices->size(),
		    sensors->size(), (*e)->hotplug() ? "events" : "unsupported (periodic enumeration)");
	UsbSensorWatch watch(**e);
	EXPECT_TRUE(watch.poll().ok());
	(*e)->waitForChange(std::chrono::milliseconds(20));
	EXPECT_TRUE(watch.poll().ok());
}

} // namespace
} // namespace ihf
