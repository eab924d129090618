#include "perception/kws/model_file.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace marvin::perception::kws {

namespace {

constexpr char kMagic[8] = {'M', 'R', 'V', 'N', 'K', 'W', 'S', '\0'};
constexpr std::uint32_t kArchitecture = 1;

static_assert(std::endian::native == std::endian::little,
              "kws model files are little-endian; add byte swapping for this target");

class Writer {
 public:
  void u32(std::uint32_t v) { raw(&v, 4); }
  void f32(float v) { raw(&v, 4); }
  void i32(int v) { u32(static_cast<std::uint32_t>(v)); }
  void raw(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    bytes.insert(bytes.end(), b, b + n);
  }
  std::vector<std::uint8_t> bytes;
};

class Reader {
 public:
  Reader(const std::vector<std::uint8_t>& bytes, std::size_t end, std::string name)
      : bytes_(bytes), end_(end), name_(std::move(name)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw ModelFileError("kws model " + name_ + ": " + what + " (at byte " +
                         std::to_string(pos_) + ")");
  }
  void raw(void* p, std::size_t n, const char* field) {
    if (end_ - pos_ < n) {
      fail(std::string("truncated: file ends inside ") + field + " (needs " + std::to_string(n) +
           " more bytes, " + std::to_string(end_ - pos_) + " left)");
    }
    std::memcpy(p, bytes_.data() + pos_, n);
    pos_ += n;
  }
  std::uint32_t u32(const char* field) {
    std::uint32_t v = 0;
    raw(&v, 4, field);
    return v;
  }
  float f32(const char* field) {
    float v = 0;
    raw(&v, 4, field);
    if (!std::isfinite(v)) {
      pos_ -= 4;
      fail(std::string(field) + " is not a finite number");
    }
    return v;
  }
  void floats(std::vector<float>& out, std::size_t n, const char* field) {
    out.resize(n);
    for (float& v : out) v = f32(field);
  }
  std::size_t pos() const { return pos_; }
  std::size_t end() const { return end_; }

 private:
  const std::vector<std::uint8_t>& bytes_;
  std::size_t end_;
  std::string name_;
  std::size_t pos_ = 0;
};

void write_features(Writer& w, const FeatureSettings& f) {
  w.i32(f.log_mel.sample_rate);
  w.i32(f.log_mel.window_ms);
  w.i32(f.log_mel.hop_ms);
  w.i32(f.log_mel.num_bins);
  w.i32(f.log_mel.fft_size);
  w.f32(f.log_mel.low_hz);
  w.f32(f.log_mel.high_hz);
  w.f32(f.log_mel.energy_floor);
  w.i32(f.frames_per_input);
  w.i32(f.input_frames);
  w.i32(f.hop_frames);
}

const int kLayerShapes[5][2] = {{kConv1Maps, kConv1In},
                                {kConv2Maps, kConv2In},
                                {kLinear, kFlat},
                                {kDense, kLinear},
                                {kClasses, kDense}};
const char* const kLayerNames[5] = {"conv1", "conv2", "linear", "dense", "output"};

}  // namespace

std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

FeatureSettings current_feature_settings() { return FeatureSettings{}; }

QuantizedNetwork KwsModel::int8_network() const {
  if (quantized) return *quantized;
  if (!(scales.input > 0.0f && scales.conv1 > 0.0f && scales.conv2 > 0.0f &&
        scales.linear > 0.0f && scales.dense > 0.0f)) {
    throw std::invalid_argument("kws model for \"" + keyword +
                                "\" has no calibrated activation scales; cannot run in int8");
  }
  return quantize(network, scales, WeightScaling::per_channel);
}

std::vector<std::uint8_t> serialize_model(const KwsModel& model, WeightType type) {
  if (model.keyword.empty() || model.keyword.size() > 64) {
    throw std::invalid_argument("kws model: keyword must have 1..64 bytes");
  }
  Writer w;
  w.raw(kMagic, 8);
  w.u32(kModelFormatVersion);
  w.u32(static_cast<std::uint32_t>(type));
  w.u32(kArchitecture);
  write_features(w, model.features);
  w.f32(model.detection.threshold);
  w.i32(model.detection.smoothing_windows);
  w.f32(model.detection.refractory_seconds);
  w.u32(static_cast<std::uint32_t>(model.keyword.size()));
  w.raw(model.keyword.data(), model.keyword.size());
  for (float m : model.normalisation.mean) w.f32(m);
  w.f32(model.normalisation.inv_std);
  const ActivationScales& s = model.scales;
  for (float v : {s.input, s.conv1, s.conv2, s.linear, s.dense}) w.f32(v);
  if (type == WeightType::float32) {
    for (const FloatLayer* l : model.network.layers()) {
      w.i32(l->out);
      w.i32(l->in);
      w.raw(l->weights.data(), l->weights.size() * 4);
      w.raw(l->bias.data(), l->bias.size() * 4);
    }
  } else {
    const QuantizedNetwork q = model.int8_network();
    for (const QuantizedLayer* l : q.layers()) {
      w.i32(l->out);
      w.i32(l->in);
      w.raw(l->weight_scales.data(), l->weight_scales.size() * 4);
      w.raw(l->weights.data(), l->weights.size());
      w.raw(l->bias.data(), l->bias.size() * 4);
    }
  }
  w.u32(crc32(w.bytes.data(), w.bytes.size()));
  return w.bytes;
}

void save_model(const std::filesystem::path& path, const KwsModel& model, WeightType type) {
  const std::vector<std::uint8_t> bytes = serialize_model(model, type);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("kws model " + path.string() + ": cannot write the file");
}

KwsModel parse_model(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  // The checksum comes last; check the header first so a wrong file gets the right message.
  Reader head(bytes, bytes.size(), name);
  char magic[8];
  head.raw(magic, 8, "magic");
  if (std::memcmp(magic, kMagic, 8) != 0) {
    throw ModelFileError("kws model " + name +
                         ": not a Marvin keyword model (bad magic at byte 0, expected \"MRVNKWS\")");
  }
  const std::uint32_t version = head.u32("version");
  if (version != kModelFormatVersion) {
    throw ModelFileError("kws model " + name + ": format version " + std::to_string(version) +
                         " is not supported (this build reads version " +
                         std::to_string(kModelFormatVersion) + ") at byte 8");
  }
  if (bytes.size() < 16) head.u32("weight type");  // reports truncation
  if (bytes.size() < 24) {
    throw ModelFileError("kws model " + name + ": truncated: " + std::to_string(bytes.size()) +
                         " bytes is shorter than the header");
  }
  std::uint32_t stored_crc = 0;
  std::memcpy(&stored_crc, bytes.data() + bytes.size() - 4, 4);
  const std::uint32_t actual_crc = crc32(bytes.data(), bytes.size() - 4);

  Reader r(bytes, bytes.size() - 4, name);
  r.raw(magic, 8, "magic");
  r.u32("version");
  const std::uint32_t type = r.u32("weight type");
  if (type != 1 && type != 2) {
    r.fail("weight type " + std::to_string(type) + " is unknown (1 = float32, 2 = int8)");
  }
  const std::uint32_t arch = r.u32("architecture");
  if (arch != kArchitecture) {
    r.fail("architecture " + std::to_string(arch) + " is unknown (1 = cnn-trad-fpool3)");
  }
  // Fields are read before the checksum is compared, so a file cut short reports the field
  // it ends in ("truncated") rather than only a checksum mismatch.
  KwsModel m;
  FeatureSettings& f = m.features;
  f.log_mel.sample_rate = static_cast<int>(r.u32("features.sample_rate"));
  f.log_mel.window_ms = static_cast<int>(r.u32("features.window_ms"));
  f.log_mel.hop_ms = static_cast<int>(r.u32("features.hop_ms"));
  f.log_mel.num_bins = static_cast<int>(r.u32("features.num_bins"));
  f.log_mel.fft_size = static_cast<int>(r.u32("features.fft_size"));
  f.log_mel.low_hz = r.f32("features.low_hz");
  f.log_mel.high_hz = r.f32("features.high_hz");
  f.log_mel.energy_floor = r.f32("features.energy_floor");
  f.frames_per_input = static_cast<int>(r.u32("features.frames_per_input"));
  f.input_frames = static_cast<int>(r.u32("features.input_frames"));
  f.hop_frames = static_cast<int>(r.u32("features.hop_frames"));
  m.detection.threshold = r.f32("detection.threshold");
  m.detection.smoothing_windows = static_cast<int>(r.u32("detection.smoothing_windows"));
  m.detection.refractory_seconds = r.f32("detection.refractory_seconds");
  if (m.detection.smoothing_windows < 1 || m.detection.smoothing_windows > 64) {
    r.fail("detection.smoothing_windows must be 1..64, got " +
           std::to_string(m.detection.smoothing_windows));
  }
  const std::uint32_t klen = r.u32("keyword length");
  if (klen < 1 || klen > 64) r.fail("keyword length must be 1..64, got " + std::to_string(klen));
  m.keyword.resize(klen);
  r.raw(m.keyword.data(), klen, "keyword");
  for (float& v : m.normalisation.mean) v = r.f32("normalisation.mean");
  m.normalisation.inv_std = r.f32("normalisation.inv_std");
  m.scales.input = r.f32("scales.input");
  m.scales.conv1 = r.f32("scales.conv1");
  m.scales.conv2 = r.f32("scales.conv2");
  m.scales.linear = r.f32("scales.linear");
  m.scales.dense = r.f32("scales.dense");

  QuantizedNetwork q;
  auto qlayers = q.layers();
  auto flayers = m.network.layers();
  for (std::size_t i = 0; i < 5; ++i) {
    const std::string lname = kLayerNames[i];
    const std::uint32_t out = r.u32("layer out");
    const std::uint32_t in = r.u32("layer in");
    if (out != static_cast<std::uint32_t>(kLayerShapes[i][0]) ||
        in != static_cast<std::uint32_t>(kLayerShapes[i][1])) {
      r.fail("layer " + lname + " is " + std::to_string(out) + "x" + std::to_string(in) +
             ", the architecture needs " + std::to_string(kLayerShapes[i][0]) + "x" +
             std::to_string(kLayerShapes[i][1]));
    }
    const std::size_t n = static_cast<std::size_t>(out) * in;
    if (type == 1) {
      FloatLayer& l = *flayers[i];
      l.out = static_cast<int>(out);
      l.in = static_cast<int>(in);
      r.floats(l.weights, n, (lname + " weights").c_str());
      r.floats(l.bias, out, (lname + " bias").c_str());
    } else {
      QuantizedLayer& l = *qlayers[i];
      l.out = static_cast<int>(out);
      l.in = static_cast<int>(in);
      r.floats(l.weight_scales, out, (lname + " scales").c_str());
      for (float s : l.weight_scales) {
        if (!(s > 0.0f)) r.fail(lname + " has a weight scale <= 0");
      }
      l.weights.resize(n);
      r.raw(l.weights.data(), n, (lname + " weights").c_str());
      r.floats(l.bias, out, (lname + " bias").c_str());
    }
  }
  if (r.pos() != r.end()) {
    r.fail(std::to_string(r.end() - r.pos()) + " unexpected bytes before the checksum");
  }
  if (stored_crc != actual_crc) {
    throw ModelFileError("kws model " + name + ": checksum mismatch at byte " +
                         std::to_string(bytes.size() - 4) +
                         " (the file is corrupt or was cut short)");
  }
  if (type == 2) {
    q.scales = m.scales;
    m.network = dequantize(q);
    m.quantized = std::move(q);
  }
  // The features must be what this build computes, or the network sees different numbers.
  const FeatureSettings cur = current_feature_settings();
  auto mismatch = [&](const char* field, double got, double want) {
    if (got != want) {
      std::ostringstream msg;
      msg << "kws model " << name << ": features." << field << " is " << got
          << " but this build's log-mel features use " << want << " (retrain the model)";
      throw ModelFileError(msg.str());
    }
  };
  mismatch("sample_rate", f.log_mel.sample_rate, cur.log_mel.sample_rate);
  mismatch("window_ms", f.log_mel.window_ms, cur.log_mel.window_ms);
  mismatch("hop_ms", f.log_mel.hop_ms, cur.log_mel.hop_ms);
  mismatch("num_bins", f.log_mel.num_bins, cur.log_mel.num_bins);
  mismatch("fft_size", f.log_mel.fft_size, cur.log_mel.fft_size);
  mismatch("low_hz", f.log_mel.low_hz, cur.log_mel.low_hz);
  mismatch("high_hz", f.log_mel.high_hz, cur.log_mel.high_hz);
  mismatch("energy_floor", f.log_mel.energy_floor, cur.log_mel.energy_floor);
  mismatch("frames_per_input", f.frames_per_input, cur.frames_per_input);
  mismatch("input_frames", f.input_frames, cur.input_frames);
  if (f.hop_frames < 1 || f.hop_frames > 1000) {
    throw ModelFileError("kws model " + name + ": features.hop_frames must be 1..1000");
  }
  return m;
}

KwsModel load_model(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelFileError("kws model " + path.string() + ": cannot open the file");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  return parse_model(bytes, path.string());
}

}  // namespace marvin::perception::kws
