// SPDX-License-Identifier: MIT
#pragma once

// The frame loop of `ihf run`, without knowing what is done with a frame:
// it opens and starts the source, takes frames with a timeout, hands each to
// a FrameProcessor, drops frames that are already too old when their turn
// comes (real-time and live only; counted), prints periodic stats, stops at
// the end of the stream, after max frames, or on SIGINT/SIGTERM, and on a
// source error reports it and reopens the source with exponential backoff
// (as many attempts in a row as configured; a delivered frame resets the
// count). Time comes from an injected PacingClock (tests run it on simulated time).
//
// A frame's arrival time, against which lateness is measured: a live
// source's host timestamp (the steady clock, as the app's clock); in
// real-time replay the time the recording's pacing made it due (the first
// frame after a start anchors the recorded timestamps to the clock, scaled
// by speed); in step mode the time next() returned it (never late).

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

#include "drivers/clock.h"
#include "drivers/frame_source.h"
#include "drivers/replay_pacer.h"
#include "firmware_app/runtime/shutdown_signal.h"

namespace ihf::app {

struct RunLoopConfig {
	bool realTime = false; // recordings: paced replay (lateness applies)
	double speed = 1.0; // of paced replay
	std::chrono::nanoseconds timeout = std::chrono::seconds(1); // per next()
	int maxRetries = 5;
	std::chrono::nanoseconds backoff = std::chrono::milliseconds(200);
	std::chrono::nanoseconds backoffMax = std::chrono::seconds(5);
	std::chrono::nanoseconds frameBudget{0}; // 0: never drop
	std::chrono::nanoseconds statsInterval = std::chrono::seconds(5); // 0: only at the end
	uint64_t maxFrames = 0; // 0: no limit
};

class FrameProcessor
{
public:
	virtual ~FrameProcessor() = default;
	// After every (re)start, with what the source reports: size buffers here.
	virtual Status prepare(const SourceInfo &info) = 0;
	// One frame; arrivalNs on the loop's clock. An error ends the run.
	virtual Status process(const Frame &frame, int64_t arrivalNs) = 0;
	// Appends the processor's part of a stats line.
	virtual void describe(std::string &line) const = 0;
	// A signal arrived while the processor waited (its own inputs).
	virtual bool interrupted() const { return false; }
};

// Whether the sensor behind a live source is plugged in (a USB watch). When
// it says the sensor is gone, the loop does not spend reopen attempts: it
// waits for the sensor to return, then reopens.
class SourcePresence
{
public:
	virtual ~SourcePresence() = default;
	// Looks for changes without blocking and reports them on log.
	virtual void update(std::FILE *log) = 0;
	virtual bool present() const = 0;
};

// Told on every loop iteration, also while waiting to reopen or for an
// unplugged sensor (the systemd watchdog, service_notify.h).
class LoopHeartbeat
{
public:
	virtual ~LoopHeartbeat() = default;
	virtual void beat() = 0;
};

struct RunCounters {
	uint64_t delivered = 0; // frames the source gave
	uint64_t processed = 0;
	uint64_t late = 0; // dropped: older than the frame budget at their turn
	uint64_t timeouts = 0;
	uint64_t sourceErrors = 0;
	uint64_t reopens = 0; // successful reopens after an error
	uint64_t unplugs = 0; // waits for an unplugged sensor to return
	SourceCounters source; // summed over every open of the source
};

enum class RunEnd {
	kEndOfStream,
	kMaxFrames,
	kShutdown,
	kSourceFailed, // retries exhausted
	kProcessFailed,
};

const char *runEndName(RunEnd end);

class RunLoop
{
public:
	RunLoop(FrameSource &source, FrameProcessor &processor, PacingClock &clock, RunLoopConfig config,
		ShutdownSignal *shutdown, std::FILE *log);

	// Checked every checkInterval while running and before each reopen.
	void setPresence(SourcePresence *presence,
			 std::chrono::nanoseconds checkInterval = std::chrono::milliseconds(500))
	{
		presence_ = presence;
		presenceInterval_ = checkInterval;
	}

	void setHeartbeat(LoopHeartbeat *heartbeat) { heartbeat_ = heartbeat; }

	RunEnd run();
	const RunCounters &counters() const { return counters_; }
	// The error that ended the run (kSourceFailed, kProcessFailed).
	const std::string &failure() const { return failure_; }
	// "frames N processed P late L ..." for the stats lines.
	std::string statsLine() const;

private:
	bool openSource(); // with retries; false: give up or shutdown
	bool backoffWait(int attempt);
	void updatePresence(bool force);
	bool waitForSensor(); // false: stop requested
	void closeSource();
	bool stopRequested();
	void maybeStats(bool force);
	void beat()
	{
		if (heartbeat_)
			heartbeat_->beat();
	}

	FrameSource &source_;
	FrameProcessor &processor_;
	PacingClock &clock_;
	RunLoopConfig config_;
	ReplayPacer pacer_; // when a paced frame is due (real time)
	ShutdownSignal *shutdown_;
	std::FILE *log_;
	RunCounters counters_;
	std::string failure_;
	bool open_ = false;
	int64_t startNs_ = 0, lastStatsNs_ = 0;
	uint64_t statsDelivered_ = 0;
	int failuresInARow_ = 0;
	uint64_t timeoutsInARow_ = 0;
	SourcePresence *presence_ = nullptr;
	std::chrono::nanoseconds presenceInterval_{0};
	int64_t lastPresenceNs_ = 0;
	bool presenceChecked_ = false;
	LoopHeartbeat *heartbeat_ = nullptr;
};

} // namespace ihf::app
