// Running a text-to-speech program that writes a WAV file (flite, festival's text2wave), for
// the training tools' synthesisers other than the linked-in espeak-ng. Tools only.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace marvin::perception::kws {

// Runs `argv` (argv[0] the program, found on PATH) with every "{out}" argument replaced by a
// fresh temporary WAV path and `input` on its standard input, and returns that file as 16 kHz
// float with the silence trimmed. Throws std::runtime_error: "cannot run PROGRAM (ROLE; run
// scripts/setup): why" when the program is missing, `failure` when it exits with an error or
// writes no sound (text2wave exits 0 after a Scheme error), and an error naming the program
// when `input` is longer than kMaxSynthesiserInput bytes.
std::vector<float> run_synthesiser(const std::vector<std::string>& argv, const std::string& role,
                                   const std::string& failure, const std::string& input = {});

// The most `input` run_synthesiser() takes: what a pipe holds before anyone reads it (the
// input is written before the program starts, so a program that dies early cannot leave the
// writer blocked or killed by SIGPIPE). Plenty for a sentence.
inline constexpr std::size_t kMaxSynthesiserInput = 4096;

}  // namespace marvin::perception::kws
