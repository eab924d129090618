#include "kws/training/generated_voices.h"

#include <espeak-ng/espeak_ng.h>
#include <espeak-ng/speak_lib.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "kws/training/dataset.h"

namespace marvin::perception::kws {
namespace {

namespace fs = std::filesystem;

// The data directory espeak-ng uses (ESPEAK_DATA_PATH's if set, else the system's).
// Resolving the path does not start the engine.
fs::path system_data_dir() {
  espeak_ng_InitializePath(nullptr);
  const char* path = nullptr;
  espeak_Info(&path);
  if (path == nullptr || !fs::is_directory(fs::path(path) / "voices" / "!v")) {
    throw std::runtime_error("espeak-ng data directory \"" + std::string(path ? path : "") +
                             "\": expected voices/!v inside (is espeak-ng-data installed?)");
  }
  return path;
}

// Links every entry of `from` into `to`, except `skip`.
void link_entries(const fs::path& from, const fs::path& to, const std::string& skip) {
  for (const auto& e : fs::directory_iterator(from)) {
    if (e.path().filename() == skip) continue;
    fs::create_symlink(e.path(), to / e.path().filename());
  }
}

}  // namespace

std::string random_variant_text(const std::string& name, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto between = [&](double lo, double hi) { return static_cast<int>(lo + (hi - lo) * u(rng)); };
  std::ostringstream out;
  out << "language variant\nname " << name << "\n";
  const int base = between(70, 220);
  out << "pitch " << base << ' ' << base + between(30, 110) << "\n";
  // One vocal-tract length for all formants (what separates a child from a large man), then
  // each formant moved a little on its own (what separates accents and voice qualities).
  const double tract = 0.8 + 0.45 * u(rng);
  const bool dull_top = u(rng) < 0.25;
  for (int f = 0; f <= 8; ++f) {
    const int freq = static_cast<int>(100.0 * tract * (0.9 + 0.2 * u(rng)));
    const int height = (f >= 6 && dull_top) ? between(0, 25) : between(60, 150);
    out << "formant " << f << ' ' << freq << ' ' << height << ' ' << between(70, 170) << "\n";
  }
  out << "voicing " << between(30, 150) << "\n";
  out << "flutter " << between(0, 15) << "\n";
  if (u(rng) < 0.3) out << "roughness " << between(0, 5) << "\n";
  return out.str();
}

std::string random_wide_variant_text(const std::string& name, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto between = [&](double lo, double hi) { return static_cast<int>(lo + (hi - lo) * u(rng)); };
  std::ostringstream out;
  out << "language variant\nname " << name << "\n";
  const int base = between(50, 240);
  out << "pitch " << base << ' ' << base + between(20, 150) << "\n";
  const double tract = 0.75 + 0.7 * u(rng);
  const bool dull_top = u(rng) < 0.25;
  for (int f = 0; f <= 8; ++f) {
    // Formants 1..5 sometimes far off the tract's scale on their own (espeak-ng's "Michael",
    // "Denis", "travis" move single formants to 40..60 %), and sometimes nearly silent.
    double scale = tract * (0.9 + 0.2 * u(rng));
    if (f >= 1 && f <= 5 && u(rng) < 0.2) scale = 0.45 + 1.05 * u(rng);
    int height = between(40, 160);
    if ((f >= 6 && dull_top) || (f >= 3 && f <= 5 && u(rng) < 0.08)) height = between(0, 30);
    out << "formant " << f << ' ' << static_cast<int>(100.0 * scale) << ' ' << height << ' '
        << between(60, 180) << "\n";
  }
  out << "voicing " << between(30, 230) << "\n";
  if (u(rng) < 0.5) out << "consonants " << between(30, 150) << ' ' << between(20, 190) << "\n";
  if (u(rng) < 0.3) {
    // The spectrum's tilt: gains at three frequencies (espeak-ng's "tone").
    out << "tone " << between(100, 650) << ' ' << between(60, 255) << ' ' << between(600, 1500)
        << ' ' << between(20, 255) << ' ' << between(1200, 4500) << ' ' << between(10, 200) << "\n";
  }
  if (u(rng) < 0.15) {
    out << "breath 0";
    const int level = between(1, 7);
    for (int i = 1; i < 8; ++i) out << ' ' << between(0, level);
    out << "\n";
  }
  if (u(rng) < 0.2) out << "echo " << between(20, 160) << ' ' << between(5, 30) << "\n";
  // The Klatt synthesiser's voice sources (espeak-ng's klatt..klatt6 variants; 4 is held out).
  if (u(rng) < 0.2) {
    static const int kSources[] = {1, 2, 3, 5, 6};
    out << "klatt " << kSources[std::uniform_int_distribution<int>(0, 4)(rng)] << "\n";
  }
  out << "flutter " << between(0, 20) << "\n";
  if (u(rng) < 0.3) out << "roughness " << between(0, 7) << "\n";
  return out.str();
}

std::vector<std::string> install_generated_variants(int count, std::uint64_t seed,
                                                    const fs::path& dir, VariantSpace space) {
  const fs::path system = system_data_dir();
  const fs::path data = dir / "espeak-ng-data";
  std::vector<std::string> names;
  try {
    if (fs::exists(dir)) throw std::runtime_error("already exists");
    fs::create_directories(data / "voices" / "!v");
    link_entries(system, data, "voices");
    link_entries(system / "voices", data / "voices", "!v");
    link_entries(system / "voices" / "!v", data / "voices" / "!v", "");
    std::mt19937_64 rng(seed);
    for (int i = 0; i < count; ++i) {
      names.push_back("mkws" + std::to_string(i));
      std::ofstream f(data / "voices" / "!v" / names.back());
      f << (space == VariantSpace::kWide ? random_wide_variant_text(names.back(), rng)
                                         : random_variant_text(names.back(), rng));
      if (!f.flush()) throw std::runtime_error("cannot write variant " + names.back());
    }
  } catch (const std::exception& e) {
    throw std::runtime_error("generated voices in \"" + dir.string() + "\": " + e.what());
  }
  return names;
}

void use_espeak_data(const fs::path& dir) {
  // espeak-ng looks for <ESPEAK_DATA_PATH>/espeak-ng-data.
  setenv("ESPEAK_DATA_PATH", dir.c_str(), 1);
}

std::vector<std::string> voices_with_variants(const std::vector<std::string>& bases,
                                              const std::vector<std::string>& variants) {
  std::vector<std::string> out;
  for (const auto& b : bases) {
    for (const auto& v : variants) out.push_back(b + "+" + v);
  }
  return out;
}

GeneratedVoiceSet::GeneratedVoiceSet(int count, std::uint64_t seed, fs::path dir,
                                     VariantSpace space) {
  if (dir.empty()) {
    dir = fs::temp_directory_path() / ("marvin-kws-voices-" + std::to_string(::getpid()));
    temporary_ = dir;
  }
  const std::vector<std::string> variants = install_generated_variants(count, seed, dir, space);
  use_espeak_data(dir);
  voices_ = training_voices();
  for (const std::string& v : voices_with_variants(training_accents(), variants))
    voices_.push_back(v);
}

GeneratedVoiceSet::~GeneratedVoiceSet() {
  std::error_code ignored;
  if (!temporary_.empty()) fs::remove_all(temporary_, ignored);
}

}  // namespace marvin::perception::kws
