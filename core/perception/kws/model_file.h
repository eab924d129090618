// A trained keyword-spotting model and its file format.
//
// File format, version 1 (all numbers little-endian; u32 = uint32, f32 = IEEE float):
//
//   offset  field
//   0       magic, 8 bytes: "MRVNKWS\0"
//   8       u32 format version (1)
//   12      u32 weight type: 1 = float32 weights, 2 = int8 weights with f32 scales
//   16      u32 architecture id: 1 = cnn-trad-fpool3, 32 x 40 input, 4 classes (network.h)
//   20      feature settings the model was trained on (log_mel.h), which the loader compares
//           with the running build's: u32 sample_rate, u32 window_ms, u32 hop_ms,
//           u32 num_bins, u32 fft_size, f32 low_hz, f32 high_hz, f32 energy_floor,
//           u32 frames averaged per input frame (3), u32 input frames (32),
//           u32 frames between windows (25 = 250 ms)
//   64      detection defaults: f32 threshold, u32 smoothing windows, f32 refractory seconds
//   76      u32 keyword length n (1..64), then n bytes of UTF-8 keyword (lower case)
//   ..      normalisation: f32 mean[num_bins], f32 inverse standard deviation
//   ..      activation scales: f32 input, conv1, conv2, linear, dense (0 when not calibrated)
//   ..      five layers, conv1, conv2, linear, dense, output, each:
//             u32 out, u32 in,
//             weight type 1: f32 weights[out*in]
//             weight type 2: f32 scales[out], i8 weights[out*in]
//             f32 bias[out]
//   end-4   u32 CRC-32 (IEEE, as zlib) of every byte before it
//
// A reader rejects a file whose version it does not know; a new field means a new version.
// Every load error is a ModelFileError whose message names the file, the field and the byte
// offset where reading stopped.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "perception/kws/network.h"
#include "perception/log_mel.h"

namespace marvin::perception::kws {

inline constexpr std::uint32_t kModelFormatVersion = 1;

struct FeatureSettings {
  LogMelOptions log_mel;           // must equal the running extractor's options
  int frames_per_input = kFramesPerInput;
  int input_frames = kInputFrames;
  int hop_frames = 25;             // a window every 250 ms
};

struct DetectionSettings {
  float threshold = 0.5f;          // on the smoothed keyword posterior
  int smoothing_windows = 3;       // posteriors averaged (consecutive windows)
  float refractory_seconds = 1.0f; // no second detection within this time of one
};

struct Normalisation {
  std::array<float, kBins> mean{};  // per-bin mean of the training features
  float inv_std = 1.0f;             // one scale for all bins
};

enum class WeightType : std::uint32_t { float32 = 1, int8 = 2 };

struct KwsModel {
  std::string keyword = "marvin";
  FeatureSettings features;
  DetectionSettings detection;
  Normalisation normalisation;
  ActivationScales scales;          // calibrated activation ranges (needed for int8)
  FloatNetwork network;             // float weights (dequantised when the file is int8)
  std::optional<QuantizedNetwork> quantized;  // the stored int8 weights, if the file had them

  // The int8 network: the stored one, or the float weights quantised per channel with
  // `scales`. Throws std::invalid_argument when the scales were never calibrated.
  QuantizedNetwork int8_network() const;
};

class ModelFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes the model (overwriting). int8 stores `quantized` if set, else quantises per channel.
// Throws std::runtime_error when the file cannot be written.
void save_model(const std::filesystem::path& path, const KwsModel& model, WeightType type);

// Serialises to / parses from bytes (what save_model / load_model write and read).
std::vector<std::uint8_t> serialize_model(const KwsModel& model, WeightType type);
KwsModel parse_model(const std::vector<std::uint8_t>& bytes, const std::string& name);

// Reads a model. Throws ModelFileError (missing file, bad magic, unknown version, wrong
// architecture, feature settings that differ from `expected_features`, truncated data,
// checksum mismatch, non-finite numbers), naming the file and the offending field.
KwsModel load_model(const std::filesystem::path& path);

// The feature settings this build's log-mel extractor produces.
FeatureSettings current_feature_settings();

// The CRC-32 (IEEE 802.3, as zlib's) that ends every model file of this folder.
std::uint32_t crc32(const std::uint8_t* data, std::size_t size);

}  // namespace marvin::perception::kws
