#include "perception/kws/embedding_head.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include "perception/kws/model_file.h"

#ifndef MARVIN_KWS_DEFAULT_HEAD
#define MARVIN_KWS_DEFAULT_HEAD "models/marvin-embedding-head.bin"
#endif

namespace marvin::perception::kws {
namespace {

constexpr char kHeadMagic[8] = {'M', 'R', 'V', 'N', 'K', 'W', 'E', '\0'};

class HeadReader {
 public:
  HeadReader(const std::vector<std::uint8_t>& bytes, std::size_t end, const std::string& name)
      : bytes_(bytes), end_(end), name_(name) {}
  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw ModelFileError(name_ + ": " + field + " at byte " + std::to_string(pos_) + ": " +
                         message);
  }
  void need(std::size_t n, const char* field) const {
    if (end_ - pos_ < n) {
      fail(field, "file ends after " + std::to_string(bytes_.size()) + " bytes (truncated)");
    }
  }
  std::uint32_t u32(const char* field) {
    need(4, field);
    std::uint32_t v = 0;
    std::memcpy(&v, bytes_.data() + pos_, 4);
    pos_ += 4;
    return v;
  }
  float f32(const char* field) {
    need(4, field);
    float v = 0.0f;
    std::memcpy(&v, bytes_.data() + pos_, 4);
    if (!std::isfinite(v)) fail(field, "not a finite number");
    pos_ += 4;
    return v;
  }
  void floats(std::vector<float>& out, const char* field) {
    for (float& v : out) v = f32(field);
  }
  std::string text(std::size_t n, const char* field) {
    need(n, field);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + pos_), n);
    pos_ += n;
    return s;
  }
  std::size_t pos() const { return pos_; }

 private:
  const std::vector<std::uint8_t>& bytes_;
  std::size_t end_;
  const std::string& name_;
  std::size_t pos_ = 0;
};

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + 4);
}
void put_f32(std::vector<std::uint8_t>& out, float v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + 4);
}

}  // namespace

void EmbeddingHead::resize(int hidden_units) {
  hidden = hidden_units;
  const auto h = static_cast<std::size_t>(hidden_units);
  w1.assign(h * kHeadInputs, 0.0f);
  b1.assign(h, 0.0f);
  w2.assign(h * h, 0.0f);
  b2.assign(h, 0.0f);
  w3.assign(h, 0.0f);
  b3 = 0.0f;
}

float EmbeddingHead::score(std::span<const float> input) const {
  const auto h = static_cast<std::size_t>(hidden);
  std::vector<float> a(h), b(h);
  // Eight partial sums: the compiler may not reorder one float sum, but it vectorises eight
  // independent ones (the first layer is nearly all of the head's arithmetic).
  static_assert(kHeadInputs % 8 == 0);
  for (std::size_t o = 0; o < h; ++o) {
    const float* w = w1.data() + o * kHeadInputs;
    std::array<float, 8> part{};
    for (std::size_t i = 0; i < static_cast<std::size_t>(kHeadInputs); i += 8) {
      for (std::size_t j = 0; j < 8; ++j) part[j] += w[i + j] * input[i + j];
    }
    float sum = b1[o];
    for (float p : part) sum += p;
    a[o] = std::max(sum, 0.0f);
  }
  for (std::size_t o = 0; o < h; ++o) {
    float sum = b2[o];
    for (std::size_t i = 0; i < h; ++i) sum += w2[o * h + i] * a[i];
    b[o] = std::max(sum, 0.0f);
  }
  float z = b3;
  for (std::size_t i = 0; i < h; ++i) z += w3[i] * b[i];
  return 1.0f / (1.0f + std::exp(-z));
}

std::vector<std::uint8_t> serialize_head(const EmbeddingHead& head) {
  std::vector<std::uint8_t> out(kHeadMagic, kHeadMagic + 8);
  put_u32(out, kHeadFormatVersion);
  put_u32(out, kHeadEmbeddings);
  put_u32(out, kEmbeddingSize);
  put_u32(out, static_cast<std::uint32_t>(head.hidden));
  put_f32(out, head.threshold);
  put_f32(out, head.refractory_seconds);
  put_u32(out, static_cast<std::uint32_t>(head.consecutive));
  put_u32(out, static_cast<std::uint32_t>(head.keyword.size()));
  out.insert(out.end(), head.keyword.begin(), head.keyword.end());
  for (const auto* v : {&head.w1, &head.b1, &head.w2, &head.b2, &head.w3}) {
    for (const float x : *v) put_f32(out, x);
  }
  put_f32(out, head.b3);
  put_u32(out, crc32(out.data(), out.size()));
  return out;
}

EmbeddingHead parse_head(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  if (bytes.size() < 12 || std::memcmp(bytes.data(), kHeadMagic, 8) != 0) {
    throw ModelFileError(name +
                         ": magic at byte 0: expected \"MRVNKWE\" (an embedding "
                         "wake-word head), found something else or a file under 12 bytes");
  }
  HeadReader r(bytes, bytes.size() - 4, name);
  r.text(8, "magic");
  const std::uint32_t version = r.u32("version");
  if (version != 1 && version != kHeadFormatVersion) {
    r.fail("version", "format version " + std::to_string(version) + ", this build reads 1 and " +
                          std::to_string(kHeadFormatVersion));
  }
  const std::uint32_t frames = r.u32("embeddings per input");
  if (frames != kHeadEmbeddings)
    r.fail("embeddings per input", std::to_string(frames) + ", expected 16");
  const std::uint32_t size = r.u32("embedding size");
  if (size != kEmbeddingSize) r.fail("embedding size", std::to_string(size) + ", expected 96");
  const std::uint32_t hidden = r.u32("hidden");
  if (hidden < 1 || hidden > 1024) r.fail("hidden", std::to_string(hidden) + ", expected 1..1024");
  EmbeddingHead head;
  head.threshold = r.f32("threshold");
  if (head.threshold < 0.0f || head.threshold > 1.0f) r.fail("threshold", "expected 0..1");
  head.refractory_seconds = r.f32("refractory seconds");
  if (head.refractory_seconds < 0.0f) r.fail("refractory seconds", "expected >= 0");
  if (version >= 2) {
    const std::uint32_t consecutive = r.u32("consecutive steps");
    if (consecutive < 1 || consecutive > 10)
      r.fail("consecutive steps", std::to_string(consecutive) + ", expected 1..10");
    head.consecutive = static_cast<int>(consecutive);
  }
  const std::uint32_t length = r.u32("keyword length");
  if (length < 1 || length > 64)
    r.fail("keyword length", std::to_string(length) + ", expected 1..64");
  head.keyword = r.text(length, "keyword");
  const std::size_t weights_at = r.pos();
  const std::size_t weights =
      (static_cast<std::size_t>(hidden) * (kHeadInputs + hidden + 3) + 1) * 4;
  // Checked before the checksum, so a short file says "truncated", not "damaged".
  const std::size_t available = bytes.size() - 4 - weights_at;
  if (available != weights) {
    r.fail("weights", std::to_string(available) + " bytes of weights, " + std::to_string(weights) +
                          " expected for hidden " + std::to_string(hidden) +
                          (available < weights ? " (truncated)" : " (extra bytes)"));
  }
  std::uint32_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 4, 4);
  if (stored != crc32(bytes.data(), bytes.size() - 4)) {
    throw ModelFileError(name + ": checksum at byte " + std::to_string(bytes.size() - 4) +
                         ": CRC-32 does not match the contents (damaged file)");
  }
  head.resize(static_cast<int>(hidden));
  r.floats(head.w1, "w1");
  r.floats(head.b1, "b1");
  r.floats(head.w2, "w2");
  r.floats(head.b2, "b2");
  r.floats(head.w3, "w3");
  head.b3 = r.f32("b3");
  return head;
}

void save_head(const std::filesystem::path& path, const EmbeddingHead& head) {
  const std::vector<std::uint8_t> bytes = serialize_head(head);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error(path.string() + ": cannot write the head file");
}

EmbeddingHead load_head(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelFileError(path.string() + ": cannot open the embedding wake-word head");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  return parse_head(bytes, path.string());
}

std::filesystem::path default_head_path() {
  if (const char* env = std::getenv("MARVIN_KWS_HEAD"); env != nullptr && *env != '\0') return env;
  return MARVIN_KWS_DEFAULT_HEAD;
}

}  // namespace marvin::perception::kws
