// SPDX-License-Identifier: MIT
#include "firmware_app/runtime/run_loop.h"

#include <algorithm>
#include <cmath>

namespace ihf::app {

const char *runEndName(RunEnd end)
{
	switch (end) {
	case RunEnd::kEndOfStream:
		return "end of stream";
	case RunEnd::kMaxFrames:
		return "max frames reached";
	case RunEnd::kShutdown:
		return "shutdown requested";
	case RunEnd::kSourceFailed:
		return "source failed";
	case RunEnd::kProcessFailed:
		return "processing failed";
	}
	return "?";
}

RunLoop::RunLoop(FrameSource &source, FrameProcessor &processor, PacingClock &clock, RunLoopConfig config,
		 ShutdownSignal *shutdown, std::FILE *log)
	: source_(source), processor_(processor), clock_(clock), config_(config),
	  pacer_(clock, config.speed), shutdown_(shutdown), log_(log)
{
}

bool RunLoop::stopRequested()
{
	return (shutdown_ && shutdown_->requested()) || processor_.interrupted();
}

void RunLoop::closeSource()
{
	if (!open_)
		return;
	source_.stop();
	const SourceCounters c = source_.counters();
	counters_.source.delivered += c.delivered;
	counters_.source.corrupt += c.corrupt;
	counters_.source.dropped += c.dropped;
	counters_.source.timeouts += c.timeouts;
	open_ = false;
}

bool RunLoop::backoffWait(int attempt)
{
	const int64_t base = config_.backoff.count();
	const int64_t wait = std::min<int64_t>(config_.backoffMax.count(),
					       base * (int64_t(1) << std::min(attempt, 30)));
	const int64_t deadline = clock_.nowNs() + wait;
	// In slices, so a signal ends the wait soon.
	const int64_t slice = std::chrono::nanoseconds(std::chrono::milliseconds(50)).count();
	for (int64_t now = clock_.nowNs(); now < deadline; now = clock_.nowNs()) {
		beat();
		if (stopRequested())
			return false;
		clock_.sleepUntil(std::min(deadline, now + slice));
	}
	return !stopRequested();
}

void RunLoop::updatePresence(bool force)
{
	if (!presence_)
		return;
	const int64_t now = clock_.nowNs();
	if (!force && presenceChecked_ && now - lastPresenceNs_ < presenceInterval_.count())
		return;
	presence_->update(log_);
	presenceChecked_ = true;
	lastPresenceNs_ = now;
}

bool RunLoop::waitForSensor()
{
	++counters_.unplugs;
	std::fprintf(log_, "ihf run: %s: the sensor is unplugged; waiting for it to return\n",
		     source_.info().uri.c_str());
	std::fflush(log_);
	const int64_t slice = std::chrono::nanoseconds(std::chrono::milliseconds(100)).count();
	while (!presence_->present()) {
		beat();
		if (stopRequested())
			return false;
		clock_.sleepUntil(clock_.nowNs() + slice);
		updatePresence(false);
	}
	std::fprintf(log_, "ihf run: %s: the sensor is back; reopening\n", source_.info().uri.c_str());
	return true;
}

bool RunLoop::openSource()
{
	const std::string &uri = source_.info().uri;
	bool retrying = failuresInARow_ > 0;
	for (;;) {
		if (retrying && presence_) {
			updatePresence(true);
			if (!presence_->present()) {
				// Attempts are for a sensor that is there; an unplugged one is waited for.
				if (!waitForSensor())
					return false;
				failuresInARow_ = 1;
			}
		}
		if (retrying) {
			if (failuresInARow_ > config_.maxRetries) {
				failure_ = uri + ": gave up after " + std::to_string(config_.maxRetries) +
					   " reopen attempt" + (config_.maxRetries == 1 ? "" : "s");
				return false;
			}
			const int64_t base = config_.backoff.count();
			const int64_t wait = std::min<int64_t>(
				config_.backoffMax.count(),
				base * (int64_t(1) << std::min(failuresInARow_ - 1, 30)));
			std::fprintf(log_, "ihf run: reopening %s in %.0f ms (attempt %d of %d)\n", uri.c_str(),
				     wait * 1e-6, failuresInARow_, config_.maxRetries);
			if (!backoffWait(failuresInARow_ - 1))
				return false;
		}
		Status st = source_.open();
		if (st) {
			st = source_.start();
			if (st)
				st = processor_.prepare(source_.info());
			if (!st)
				source_.stop();
		}
		if (st) {
			open_ = true;
			pacer_.reset();
			if (retrying) {
				++counters_.reopens;
				std::fprintf(log_, "ihf run: %s reopened\n", source_.info().uri.c_str());
			}
			return true;
		}
		std::fprintf(log_, "ihf run: %s\n", st.error().message.c_str());
		++counters_.sourceErrors;
		if (config_.maxRetries == 0) {
			failure_ = st.error().message;
			return false;
		}
		++failuresInARow_;
		retrying = true;
	}
}

std::string RunLoop::statsLine() const
{
	SourceCounters s = counters_.source;
	if (open_) {
		const SourceCounters c = source_.counters();
		s.corrupt += c.corrupt;
		s.dropped += c.dropped;
	}
	char buf[256];
	std::snprintf(buf, sizeof(buf),
		      "frames %llu processed %llu late %llu corrupt %llu gaps %llu timeouts %llu "
		      "source-errors %llu reopens %llu unplugs %llu",
		      static_cast<unsigned long long>(counters_.delivered),
		      static_cast<unsigned long long>(counters_.processed),
		      static_cast<unsigned long long>(counters_.late),
		      static_cast<unsigned long long>(s.corrupt), static_cast<unsigned long long>(s.dropped),
		      static_cast<unsigned long long>(counters_.timeouts),
		      static_cast<unsigned long long>(counters_.sourceErrors),
		      static_cast<unsigned long long>(counters_.reopens),
		      static_cast<unsigned long long>(counters_.unplugs));
	std::string line = buf;
	processor_.describe(line);
	return line;
}

void RunLoop::maybeStats(bool force)
{
	const int64_t now = clock_.nowNs();
	const int64_t interval = config_.statsInterval.count();
	if (!force && (interval <= 0 || now - lastStatsNs_ < interval))
		return;
	const double seconds = (now - lastStatsNs_) * 1e-9;
	const double fps = seconds > 0 ? (counters_.delivered - statsDelivered_) / seconds : 0;
	std::fprintf(log_, "ihf run: stats: %s; %.1f frames/s\n", statsLine().c_str(), fps);
	std::fflush(log_);
	lastStatsNs_ = now;
	statsDelivered_ = counters_.delivered;
}

RunEnd RunLoop::run()
{
	startNs_ = lastStatsNs_ = clock_.nowNs();
	updatePresence(true);
	if (!openSource())
		return stopRequested() ? RunEnd::kShutdown : RunEnd::kSourceFailed;

	Frame frame;
	RunEnd end = RunEnd::kEndOfStream;
	for (;;) {
		beat();
		if (stopRequested()) {
			end = RunEnd::kShutdown;
			break;
		}
		Expected<FrameOutcome> r = source_.next(frame, config_.timeout);
		updatePresence(false);
		if (!r) {
			std::fprintf(log_, "ihf run: %s\n", r.error().message.c_str());
			++counters_.sourceErrors;
			closeSource();
			if (config_.maxRetries == 0) {
				failure_ = r.error().message;
				end = RunEnd::kSourceFailed;
				break;
			}
			++failuresInARow_;
			if (!openSource()) {
				end = stopRequested() ? RunEnd::kShutdown : RunEnd::kSourceFailed;
				break;
			}
			continue;
		}
		if (*r == FrameOutcome::kEndOfStream)
			break;
		if (*r == FrameOutcome::kTimeout) {
			++counters_.timeouts;
			// Reported at the 1st, 10th, 100th... timeout in a row.
			++timeoutsInARow_;
			const bool decade = timeoutsInARow_ == 1 || timeoutsInARow_ == 10 || timeoutsInARow_ == 100 ||
					    timeoutsInARow_ % 1000 == 0;
			if (source_.info().live && decade)
				std::fprintf(log_, "ihf run: %s: no frame in %.0f ms (%llu times in a row)\n",
					     source_.info().uri.c_str(), config_.timeout.count() * 1e-6,
					     static_cast<unsigned long long>(timeoutsInARow_));
			maybeStats(false);
			continue;
		}
		failuresInARow_ = 0;
		timeoutsInARow_ = 0;
		++counters_.delivered;
		const int64_t now = clock_.nowNs();
		int64_t arrival = now;
		bool paced = false;
		if (source_.info().live) {
			arrival = frame.hostTimestampNs;
			paced = true;
		} else if (config_.realTime) {
			arrival = pacer_.due(frame.hostTimestampNs);
			paced = true;
		}
		if (paced && config_.frameBudget.count() > 0 && now - arrival > config_.frameBudget.count()) {
			++counters_.late;
		} else {
			Status st = processor_.process(frame, arrival);
			if (!st) {
				failure_ = st.error().message;
				end = RunEnd::kProcessFailed;
				break;
			}
			++counters_.processed;
		}
		if (config_.maxFrames && counters_.delivered >= config_.maxFrames) {
			end = RunEnd::kMaxFrames;
			break;
		}
		maybeStats(false);
	}
	closeSource();
	return end;
}

} // namespace ihf::app
