// Random espeak-ng voice variants, for training on more speakers than espeak-ng ships.
//
// A variant is a small text file (voices/!v/<name> in espeak-ng's data directory) that sets
// the pitch, the nine formants' frequency, height and width, voicing, flutter and roughness.
// espeak-ng reads variants only from its data directory, so install_generated_variants()
// builds a private one: links to every entry of the system's directory, plus the generated
// variants; use_espeak_data() points the process at it. Voices are then named
// "<language>+<variant>" like the shipped ones ("en-us+mkws3").
// With more than about 20 variants espeak-ng warns on stderr that its voice list is full
// (it lists at most 349 voices). Harmless: a variant named in a voice loads from its file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace marvin::perception::kws {

// The text of one random variant called `name`. Ranges span the variants espeak-ng ships
// (pitch base 70..220 Hz; formant frequencies scaled 0.8..1.25, one scale for the whole
// vocal tract times a per-formant jitter of +-10%; heights 60..150%, the top three
// sometimes nearly off; voicing 30..150%).
std::string random_variant_text(const std::string& name, std::mt19937_64& rng);

// The same, drawn from the wider space the shipped training variants span (dataset.cpp's
// kTrainVariants, not the held-out ones): pitch base 50..240 Hz; vocal tract 0.75..1.45; a
// fifth of formants 1..5 moved on their own to 45..150 %, a few nearly silent; voicing
// 30..230 %; and sometimes consonant strength, spectral tilt ("tone"), breath, echo and the
// Klatt synthesiser's voice sources 1, 2, 3, 5, 6.
std::string random_wide_variant_text(const std::string& name, std::mt19937_64& rng);

// Which of the two generators a training run draws its variants from.
enum class VariantSpace { kNarrow, kWide };

// Writes `count` variants named mkws0, mkws1, ... (from `seed`) into a private espeak-ng
// data directory `dir`/espeak-ng-data (`dir` is created and must not exist yet). Returns
// the variant names. Throws std::runtime_error naming `dir` when it exists or cannot be
// written, or when the system's data cannot be found.
std::vector<std::string> install_generated_variants(int count, std::uint64_t seed,
                                                    const std::filesystem::path& dir,
                                                    VariantSpace space = VariantSpace::kNarrow);

// Makes espeak-ng in this process read its data from `dir` (as installed above) by setting
// ESPEAK_DATA_PATH. Has an effect only before the process first synthesises speech:
// espeak-ng reads its data path once.
void use_espeak_data(const std::filesystem::path& dir);

// Every `bases` voice with every variant ("en+mkws0", ...).
std::vector<std::string> voices_with_variants(const std::vector<std::string>& bases,
                                              const std::vector<std::string>& variants);

// The generated variants of one training run: installs `count` variants (seed `seed`) into
// `dir`, or into a temporary directory that the destructor removes when `dir` is empty; points
// espeak-ng at them (before any synthesis); voices() lists training_voices() followed by every
// training accent with every variant. Throws as install_generated_variants().
class GeneratedVoiceSet {
 public:
  GeneratedVoiceSet(int count, std::uint64_t seed, std::filesystem::path dir,
                    VariantSpace space = VariantSpace::kNarrow);
  ~GeneratedVoiceSet();
  GeneratedVoiceSet(const GeneratedVoiceSet&) = delete;
  GeneratedVoiceSet& operator=(const GeneratedVoiceSet&) = delete;
  const std::vector<std::string>& voices() const { return voices_; }

 private:
  std::filesystem::path temporary_;
  std::vector<std::string> voices_;
};

}  // namespace marvin::perception::kws
