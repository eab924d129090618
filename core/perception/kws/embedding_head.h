// The keyword head of the embedding wake word (issue 21): a small network over the last 16
// speech embeddings (speech_embedding.h, 16 x 96 numbers = 1.28 s of audio) that says how
// likely the keyword just ended. Trained by tools/kws (marvin-kws-train --embedding).
//
// Network: flatten 16 x 96 -> dense `hidden` + ReLU -> dense `hidden` + ReLU -> dense 1 ->
// sigmoid (openWakeWord's default head shape, without its layer norms). Several trained heads
// merged into one (tools/kws merge_heads(): their mean logit) are such a network, only wider.
//
// File format, version 2 (little-endian; u32 = uint32, f32 = IEEE float):
//
//   offset  field
//   0       magic, 8 bytes: "MRVNKWE\0"
//   8       u32 format version (2)
//   12      u32 embeddings per input (16), u32 numbers per embedding (96), u32 hidden (1..1024)
//   24      detection defaults: f32 threshold (0..1), f32 refractory seconds (>= 0),
//   32      u32 consecutive steps (1..10: how many 80 ms scores in a row must reach the threshold)
//   36      u32 keyword length n (1..64), then n bytes of UTF-8 keyword (lower case)
//   ..      f32 w1[hidden * 1536], b1[hidden], w2[hidden * hidden], b2[hidden], w3[hidden], b3
//   end-4   u32 CRC-32 (IEEE, as zlib) of every byte before it
//
// Version 1 is version 2 without the consecutive steps (read as 1); writers write version 2.
// A reader rejects unknown versions, other input shapes, truncated or longer files, checksum
// mismatches and non-finite numbers, with a ModelFileError (model_file.h) naming the file,
// the field and the byte offset.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "perception/kws/speech_embedding.h"

namespace marvin::perception::kws {

inline constexpr int kHeadEmbeddings = 16;
inline constexpr int kHeadInputs = kHeadEmbeddings * kEmbeddingSize;
inline constexpr std::uint32_t kHeadFormatVersion = 2;

struct EmbeddingHead {
  std::string keyword = "marvin";
  int hidden = 32;
  float threshold = 0.5f;
  float refractory_seconds = 1.0f;
  // A detection needs this many consecutive scores at or over the threshold: a spoken keyword
  // scores high for several 80 ms steps, a chance look-alike mostly for one.
  int consecutive = 1;
  std::vector<float> w1, b1, w2, b2, w3;  // row-major: w1 is hidden x 1536
  float b3 = 0.0f;

  // Zero weights of the right sizes.
  void resize(int hidden_units);
  // The keyword probability for 16 embeddings, oldest first (1536 numbers).
  float score(std::span<const float> input) const;
};

std::vector<std::uint8_t> serialize_head(const EmbeddingHead& head);
EmbeddingHead parse_head(const std::vector<std::uint8_t>& bytes, const std::string& name);
// Writes (overwriting); throws std::runtime_error when the file cannot be written.
void save_head(const std::filesystem::path& path, const EmbeddingHead& head);
// Throws ModelFileError (missing file or any of the format errors above).
EmbeddingHead load_head(const std::filesystem::path& path);

// The head the build ships: $MARVIN_KWS_HEAD if set, else models/marvin-embedding-head.bin of
// the source tree.
std::filesystem::path default_head_path();

}  // namespace marvin::perception::kws
