#include "kws/training/flite_voices.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "devices/audio/sound_buffer.h"
#include "devices/audio/sound_file.h"
#include "kws/training/augment.h"

extern char** environ;

namespace marvin::perception::kws {

const std::vector<std::string>& flite_voices() {
  static const std::vector<std::string> voices = {"kal16", "awb", "rms", "slt"};
  return voices;
}

std::vector<float> synthesize_flite(const std::string& text, const std::string& voice,
                                    float stretch, float f0_hz) {
  const auto& known = flite_voices();
  if (std::find(known.begin(), known.end(), voice) == known.end()) {
    // flite itself falls back to its default voice without a word: refuse here instead.
    throw std::runtime_error("flite voice \"" + voice + "\": expected one of kal16, awb, rms, slt");
  }
  // One temporary file per call: flite writes only to files or the sound device.
  static int counter = 0;
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() /
      ("marvin-flite-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + ".wav");
  const std::string stretch_arg = "duration_stretch=" + std::to_string(stretch);
  const std::string f0_arg = "int_f0_target_mean=" + std::to_string(f0_hz);
  const std::string out_arg = out.string();
  const char* argv[] = {
      "flite",        "-voice", voice.c_str(), "--setf", stretch_arg.c_str(), "--setf",
      f0_arg.c_str(), "-t",     text.c_str(),  "-o",     out_arg.c_str(),     nullptr};
  pid_t pid = 0;
  const int err =
      posix_spawnp(&pid, "flite", nullptr, nullptr, const_cast<char* const*>(argv), environ);
  if (err != 0) {
    throw std::runtime_error(
        "cannot run flite (the training tools' second synthesiser; run scripts/setup): " +
        std::string(std::strerror(err)));
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::filesystem::remove(out);
    throw std::runtime_error("flite -voice " + voice + " failed on \"" + text + "\"");
  }
  const std::vector<std::int16_t> pcm = audio::read_speech_file(out);
  std::filesystem::remove(out);
  return trim_silence(audio::to_float(pcm));
}

}  // namespace marvin::perception::kws
