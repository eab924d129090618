// Running a text-to-speech program that writes a WAV file (flite, festival's text2wave), for
// the training tools' synthesisers other than the linked-in espeak-ng. Tools only.
#pragma once

#include <string>
#include <vector>

namespace marvin::perception::kws {

// Runs `argv` (argv[0] the program, found on PATH) with every "{out}" argument replaced by a
// fresh temporary WAV path, and returns that file as 16 kHz float with the silence trimmed.
// Throws std::runtime_error: "cannot run PROGRAM (ROLE; run scripts/setup): why" when the
// program is missing, `failure` when it exits with an error or writes no sound (text2wave
// exits 0 after a Scheme error).
std::vector<float> run_synthesiser(const std::vector<std::string>& argv, const std::string& role,
                                   const std::string& failure);

}  // namespace marvin::perception::kws
