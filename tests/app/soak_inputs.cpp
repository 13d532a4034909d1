// SPDX-License-Identifier: MIT
#include "tests/app/soak_inputs.h"

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drivers/recording_reader.h"
#include "drivers/recording_writer.h"

namespace ihf::test {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Damages the record at `offset` so that the reader reports it corrupt,
// each kind in turn: a payload byte, a byte of the record header (its
// device timestamp, under the CRC), the record's magic.
void damage(std::vector<char> &bytes, uint64_t offset, uint64_t kind)
{
	const uint64_t at = kind % 3 == 0   ? offset + recording::kFrameHeaderSize + 20
			    : kind % 3 == 1 ? offset + 20
					    : offset;
	bytes[at] = static_cast<char>(bytes[at] ^ 0x5a);
}

Status writeBytes(const fs::path &file, const std::vector<char> &bytes)
{
	std::ofstream out(file, std::ios::binary | std::ios::trunc);
	out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
	out.close();
	if (!out)
		return makeError(Errc::kIo, file.string() + ": cannot write");
	return {};
}

// Every corruptEvery-th frame, never the first or the last.
bool damaged(uint64_t position, uint64_t records, int corruptEvery)
{
	return corruptEvery > 0 && position > 0 && position + 1 < records &&
	       (position + 1) % static_cast<uint64_t>(corruptEvery) == 0;
}

} // namespace

uint64_t corruptFramesPerPass(uint64_t records, int corruptEvery)
{
	uint64_t n = 0;
	for (uint64_t i = 0; i < records; ++i)
		n += damaged(i, records, corruptEvery);
	return n;
}

Expected<SoakInputs> makeSoakInputs(const fs::path &recording, const fs::path &boxLines, const SoakFaults &faults,
				    const fs::path &outDir)
{
	Expected<RecordingReader> reader = RecordingReader::open(recording);
	if (!reader)
		return reader.error();
	const size_t n = reader->frameCount();
	if (n < 3)
		return makeError(Errc::kInvalidArgument, recording.string() + ": a soak needs at least 3 frames");
	if (faults.passes == 0)
		return makeError(Errc::kInvalidArgument, "a soak needs at least one pass");
	std::error_code ec;
	fs::create_directories(outDir, ec);

	SoakInputs in;
	in.recordsPerPass = n;
	uint64_t lo = reader->entry(0).frameIndex, hi = lo;
	for (size_t i = 0; i < n; ++i) {
		lo = std::min(lo, reader->entry(i).frameIndex);
		hi = std::max(hi, reader->entry(i).frameIndex);
	}
	in.indexSpan = hi - lo + 1;

	std::vector<bool> corrupt(n, false);
	for (size_t i = 0; i < n; ++i)
		if (damaged(i, n, faults.corruptEvery)) {
			corrupt[i] = true;
			++in.corruptPerPass;
		}
	in.goodFrames = (n - in.corruptPerPass) * faults.passes;
	in.corruptFrames = in.corruptPerPass * faults.passes;

	// faulty.rec: the file's bytes with the chosen records damaged.
	std::ifstream src(recording, std::ios::binary);
	std::vector<char> bytes((std::istreambuf_iterator<char>(src)), {});
	if (bytes.size() != reader->fileSize())
		return makeError(Errc::kIo, recording.string() + ": cannot read");
	uint64_t kind = 0;
	for (size_t i = 0; i < n; ++i)
		if (corrupt[i])
			damage(bytes, reader->entry(i).offset, kind++);
	if (Status st = writeBytes(outDir / "faulty.rec", bytes); !st)
		return st.error();

	// clean.rec: the good frames, as recorded.
	Image<uint16_t> depth(reader->header().intrinsics.width, reader->header().intrinsics.height);
	recording::FrameRecord rec;
	std::vector<uint64_t> goodIndices;
	{
		RecordingWriterOptions o;
		o.compress = true;
		o.reserveFrames = n;
		Expected<RecordingWriter> w = RecordingWriter::create(outDir / "clean.rec", reader->header(), o);
		if (!w)
			return w.error();
		for (size_t i = 0; i < n; ++i) {
			Expected<FrameCheck> check = reader->read(i, rec, depth.view());
			if (!check)
				return check.error();
			if (*check != FrameCheck::kOk)
				return makeError(Errc::kCorrupt, recording.string() + ": frame " + std::to_string(i) +
									 " is already corrupt");
			if (corrupt[i])
				continue;
			goodIndices.push_back(rec.index);
			if (Status st = w->append({rec.index, rec.deviceTimestampNs, rec.hostTimestampNs}, depth.view());
			    !st)
				return st.error();
		}
		if (Status st = w->finish(); !st)
			return st.error();
	}

	// The box lines of one pass, parsed once.
	std::ifstream linesIn(boxLines);
	if (!linesIn)
		return makeError(Errc::kNotFound, boxLines.string() + ": cannot open");
	std::vector<json> pass;
	for (std::string line; std::getline(linesIn, line);) {
		if (line.empty())
			continue;
		json j = json::parse(line, nullptr, false);
		if (j.is_discarded() || !j.contains("frame") || !j.contains("boxes"))
			return makeError(Errc::kParse, boxLines.string() + ": not a box line: " + line);
		pass.push_back(std::move(j));
	}
	auto isGood = [&](uint64_t frame) {
		return std::find(goodIndices.begin(), goodIndices.end(), frame) != goodIndices.end();
	};

	std::ofstream faulty(outDir / "faulty.boxes.jsonl"), clean(outDir / "clean.boxes.jsonl");
	const json unknownBox = {{"obj_id", faults.unknownObjId}, {"bbox", {20, 20, 40, 40}}};
	for (uint64_t p = 0; p < faults.passes; ++p) {
		for (const json &base : pass) {
			const uint64_t recorded = base["frame"].get<uint64_t>();
			json j = base;
			j["frame"] = recorded + p * in.indexSpan;
			const std::string intact = j.dump();
			++in.lines;
			const bool truncate = faults.truncateEvery > 0 && in.lines % faults.truncateEvery == 0;
			const bool unknown = faults.unknownEvery > 0 && in.lines % faults.unknownEvery == 0;
			const bool good = isGood(recorded);
			std::string line = intact;
			if (unknown) {
				j["boxes"].insert(j["boxes"].begin(), unknownBox);
				line = j.dump();
			}
			if (truncate) {
				line.resize(line.size() / 2);
				++in.truncatedLines;
			} else if (unknown && good) {
				++in.unknownBoxes;
			}
			faulty << line << "\n";
			if (good && !truncate)
				clean << intact << "\n";
		}
	}
	faulty.close();
	clean.close();
	if (!faulty || !clean)
		return makeError(Errc::kIo, (outDir / "faulty.boxes.jsonl").string() + ": cannot write");
	return in;
}

} // namespace ihf::test
