// SPDX-License-Identifier: MIT
// ihf_soak_inputs: writes the inputs of an `ihf run` soak (soak_inputs.h)
// and prints what the run must count, as KEY=VALUE lines for a shell:
//   ihf_soak_inputs --recording R.rec --boxes R.boxes.jsonl --out DIR --frames N
//                   [--corrupt-every 7] [--truncate-every 11] [--unknown-every 5]
// --frames is the least number of good frames to play: the box lines cover
// as many whole passes over the recording as that takes.

#include <cstdio>
#include <cstdlib>
#include <string>

#include "drivers/recording_reader.h"
#include "tests/app/soak_inputs.h"

int main(int argc, char **argv)
{
	std::string recording, boxes, out;
	long long frames = 0;
	ihf::test::SoakFaults faults;
	faults.corruptEvery = 7;
	faults.truncateEvery = 11;
	faults.unknownEvery = 5;
	for (int i = 1; i + 1 < argc; i += 2) {
		const std::string key = argv[i], value = argv[i + 1];
		if (key == "--recording")
			recording = value;
		else if (key == "--boxes")
			boxes = value;
		else if (key == "--out")
			out = value;
		else if (key == "--frames")
			frames = std::atoll(value.c_str());
		else if (key == "--corrupt-every")
			faults.corruptEvery = std::atoi(value.c_str());
		else if (key == "--truncate-every")
			faults.truncateEvery = std::atoi(value.c_str());
		else if (key == "--unknown-every")
			faults.unknownEvery = std::atoi(value.c_str());
		else {
			std::fprintf(stderr, "ihf_soak_inputs: unknown option %s\n", key.c_str());
			return 2;
		}
	}
	if (argc % 2 == 0 || recording.empty() || boxes.empty() || out.empty() || frames <= 0) {
		std::fprintf(stderr, "usage: ihf_soak_inputs --recording R.rec --boxes B.jsonl --out DIR --frames N "
				     "[--corrupt-every N] [--truncate-every N] [--unknown-every N]\n");
		return 2;
	}
	auto reader = ihf::RecordingReader::open(recording);
	if (!reader) {
		std::fprintf(stderr, "ihf_soak_inputs: %s\n", reader.error().message.c_str());
		return 1;
	}
	const uint64_t perPass = reader->frameCount();
	if (perPass == 0) {
		std::fprintf(stderr, "ihf_soak_inputs: %s has no frames\n", recording.c_str());
		return 1;
	}
	const uint64_t goodPerPass = perPass - ihf::test::corruptFramesPerPass(perPass, faults.corruptEvery);
	faults.passes = (static_cast<uint64_t>(frames) + goodPerPass - 1) / goodPerPass;
	auto made = ihf::test::makeSoakInputs(recording, boxes, faults, out);
	if (!made) {
		std::fprintf(stderr, "ihf_soak_inputs: %s\n", made.error().message.c_str());
		return 1;
	}
	const ihf::test::SoakInputs &s = *made;
	std::printf("passes=%llu\nrecords_per_pass=%llu\ncorrupt_per_pass=%llu\ngood_frames=%llu\ncorrupt_frames=%llu\n"
		    "lines=%llu\ntruncated_lines=%llu\nunknown_boxes=%llu\n",
		    static_cast<unsigned long long>(faults.passes), static_cast<unsigned long long>(s.recordsPerPass),
		    static_cast<unsigned long long>(s.corruptPerPass), static_cast<unsigned long long>(s.goodFrames),
		    static_cast<unsigned long long>(s.corruptFrames), static_cast<unsigned long long>(s.lines),
		    static_cast<unsigned long long>(s.truncatedLines), static_cast<unsigned long long>(s.unknownBoxes));
	return 0;
}
