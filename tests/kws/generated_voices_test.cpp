// Generated espeak-ng variants: the variant text, the private data directory, and that the
// real espeak-ng (its command-line program, so this process's engine is left alone) speaks
// differently with each generated variant and exactly as before with a shipped voice.
#include <doctest/doctest.h>

#include <map>
#include <random>
#include <sstream>

#include "kws/training/generated_voices.h"
#include "support/child_process.h"
#include "support/files.h"

namespace kws = marvin::perception::kws;
namespace ts = marvin::test_support;

namespace {

// espeak-ng's WAV output for `voice` saying "marvin", with the data directory `data` (or the
// system's when empty).
std::string speak(const std::string& voice, const std::filesystem::path& data) {
  ts::ChildOptions o;
  if (!data.empty()) o.environment.push_back("ESPEAK_DATA_PATH=" + data.string());
  o.err = ts::ChildStream::kNull;
  ts::ChildProcess p = ts::ChildProcess::shell("espeak-ng --stdout -v '" + voice + "' marvin", o);
  REQUIRE(p.finish() == 0);
  const std::string wav = p.output();
  REQUIRE(wav.size() > 1000);
  return wav;
}

// Keyword -> numbers of each line ("formant 2 103 138 85" under "formant 2").
std::map<std::string, std::vector<int>> parse(const std::string& text) {
  std::map<std::string, std::vector<int>> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "formant") {
      std::string n;
      words >> n;
      key += " " + n;
    }
    int v;
    while (words >> v) out[key].push_back(v);
  }
  return out;
}

}  // namespace

TEST_CASE("a random variant sets pitch, nine formants and voicing inside the documented ranges") {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 50; ++i) {
    const std::string text = kws::random_variant_text("v" + std::to_string(i), rng);
    CHECK(text.rfind("language variant\nname v" + std::to_string(i) + "\n", 0) == 0);
    const auto values = parse(text);
    REQUIRE(values.count("pitch") == 1);
    const std::vector<int>& pitch = values.at("pitch");
    REQUIRE(pitch.size() == 2);
    CHECK(pitch[0] >= 70);
    CHECK(pitch[0] <= 220);
    CHECK(pitch[1] > pitch[0]);
    for (int f = 0; f <= 8; ++f) {
      const std::string key = "formant " + std::to_string(f);
      REQUIRE(values.count(key) == 1);
      const std::vector<int>& v = values.at(key);
      REQUIRE(v.size() == 3);
      CHECK(v[0] >= 72);   // 0.8 x 0.9
      CHECK(v[0] <= 138);  // 1.25 x 1.1
      CHECK(v[1] >= 0);
      CHECK(v[1] <= 150);
      if (f < 6) CHECK(v[1] >= 60);
    }
    REQUIRE(values.count("voicing") == 1);
    CHECK(values.at("voicing")[0] >= 30);
    CHECK(values.at("voicing")[0] <= 150);
  }
  std::mt19937_64 a(3), b(3);
  CHECK(kws::random_variant_text("x", a) == kws::random_variant_text("x", b));
}

TEST_CASE("a wide variant stays in the shipped training variants' ranges and uses their extras") {
  std::mt19937_64 rng(9);
  std::map<std::string, int> lines_with;  // how many variants set each keyword
  int single_formant_moved = 0;
  for (int i = 0; i < 300; ++i) {
    const auto values = parse(kws::random_wide_variant_text("w" + std::to_string(i), rng));
    const std::vector<int>& pitch = values.at("pitch");
    REQUIRE(pitch.size() == 2);
    CHECK(pitch[0] >= 50);
    CHECK(pitch[0] <= 240);
    CHECK(pitch[1] >= pitch[0] + 20);
    bool moved = false;
    for (int f = 0; f <= 8; ++f) {
      const std::vector<int>& v = values.at("formant " + std::to_string(f));
      REQUIRE(v.size() == 3);
      CHECK(v[0] >= 45);
      CHECK(v[0] <= 159);  // 1.45 x 1.1
      CHECK(v[1] >= 0);
      CHECK(v[1] <= 160);
      if (v[0] < 67) moved = true;  // below what the vocal tract's scale alone reaches
    }
    single_formant_moved += moved;
    CHECK(values.at("voicing")[0] >= 30);
    CHECK(values.at("voicing")[0] <= 230);
    for (const auto& [key, v] : values) ++lines_with[key];
    if (values.count("klatt")) CHECK(values.at("klatt")[0] != 4);  // the held-out "klatt4"
    if (values.count("tone")) CHECK(values.at("tone").size() == 6);
    if (values.count("breath")) CHECK(values.at("breath").size() == 8);
  }
  for (const char* extra : {"consonants", "tone", "breath", "echo", "klatt", "roughness"}) {
    INFO(extra);
    CHECK(lines_with[extra] > 15);
    CHECK(lines_with[extra] < 200);
  }
  CHECK(single_formant_moved > 15);
  std::mt19937_64 a(4), b(4), c(4), d(4);
  CHECK(kws::random_wide_variant_text("x", a) == kws::random_wide_variant_text("x", b));
  CHECK(kws::random_wide_variant_text("x", c) != kws::random_variant_text("x", d));
}

TEST_CASE("wide generated variants: written to the private directory, and espeak-ng reads them") {
  ts::TempDir tmp;
  const std::filesystem::path dir = tmp / "voices";
  const std::vector<std::string> names =
      kws::install_generated_variants(2, 11, dir, kws::VariantSpace::kWide);
  const std::filesystem::path variants = dir / "espeak-ng-data" / "voices" / "!v";
  std::mt19937_64 rng(11);
  for (const std::string& n : names)
    CHECK(ts::read_text(variants / n) == kws::random_wide_variant_text(n, rng));
  const std::string plain = speak("en-us", dir);
  CHECK(speak("en-us+mkws0", dir) != plain);
  CHECK(speak("en-us+mkws1", dir) != plain);
}

TEST_CASE("generated variants: a private data directory espeak-ng speaks them from") {
  ts::TempDir tmp;
  const std::filesystem::path dir = tmp / "voices";
  const std::vector<std::string> names = kws::install_generated_variants(3, 11, dir);
  REQUIRE(names == std::vector<std::string>{"mkws0", "mkws1", "mkws2"});
  const std::filesystem::path variants = dir / "espeak-ng-data" / "voices" / "!v";
  std::mt19937_64 rng(11);
  for (const std::string& n : names) CHECK(ts::read_text(variants / n) == kws::random_variant_text(n, rng));
  CHECK(std::filesystem::exists(variants / "f1"));  // the shipped variants are still there
  CHECK(std::filesystem::exists(dir / "espeak-ng-data" / "phontab"));

  CHECK(kws::voices_with_variants({"en", "en-us"}, {"mkws0", "mkws1"}) ==
        std::vector<std::string>{"en+mkws0", "en+mkws1", "en-us+mkws0", "en-us+mkws1"});

  // A shipped voice sounds exactly as with the system's data; each generated variant
  // sounds different from the plain voice and from each other (espeak-ng falls back to
  // the plain voice for a variant it cannot find, so "different" means it was read).
  CHECK(speak("en-us+m3", dir) == speak("en-us+m3", {}));
  const std::string plain = speak("en", dir);
  const std::string v0 = speak("en+mkws0", dir), v1 = speak("en+mkws1", dir);
  CHECK(v0 != plain);
  CHECK(v1 != plain);
  CHECK(v0 != v1);
  CHECK(speak("en+mkws0", {}) == speak("en", {}));  // unknown without the private data
}

TEST_CASE("generated variants refuse a directory that exists and leave it untouched") {
  ts::TempDir tmp;
  ts::write_text(tmp / "voices" / "keep.txt", "mine");
  try {
    kws::install_generated_variants(2, 1, tmp / "voices");
    FAIL("expected an error");
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    CHECK(msg.find((tmp / "voices").string()) != std::string::npos);
    CHECK(msg.find("already exists") != std::string::npos);
  }
  CHECK(ts::read_text(tmp / "voices" / "keep.txt") == "mine");
  CHECK(std::distance(std::filesystem::directory_iterator(tmp / "voices"), {}) == 1);
}
