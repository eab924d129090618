// Model files: round trips in both weight types, and every kind of bad file rejected with a
// message naming what is wrong.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "perception/kws/model_file.h"

namespace kws = marvin::perception::kws;

namespace {

kws::KwsModel sample_model() {
  kws::KwsModel m;
  m.keyword = "marvin";
  m.network = kws::make_initialised_network(9);
  for (std::size_t b = 0; b < m.normalisation.mean.size(); ++b) m.normalisation.mean[b] = -10.0f + static_cast<float>(b) * 0.1f;
  m.normalisation.inv_std = 0.25f;
  m.scales = {0.03f, 0.05f, 0.07f, 0.11f, 0.13f};
  m.detection = {0.72f, 4, 1.5f};
  return m;
}

std::string load_error(const std::vector<std::uint8_t>& bytes) {
  try {
    kws::parse_model(bytes, "test.bin");
  } catch (const kws::ModelFileError& e) {
    return e.what();
  }
  return "no error";
}

void put_u32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) { std::memcpy(b.data() + at, &v, 4); }

// Recomputes the trailing checksum so that a test reaches the field check it is aiming at.
void fix_crc(std::vector<std::uint8_t>& b) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i + 4 < b.size(); ++i) {
    c ^= b[i];
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  put_u32(b, b.size() - 4, c ^ 0xFFFFFFFFu);
}

}  // namespace

TEST_CASE("float model round trip keeps every number") {
  const kws::KwsModel m = sample_model();
  const auto bytes = kws::serialize_model(m, kws::WeightType::float32);
  const kws::KwsModel r = kws::parse_model(bytes, "mem");
  CHECK(r.keyword == "marvin");
  CHECK(r.detection.threshold == 0.72f);
  CHECK(r.detection.smoothing_windows == 4);
  CHECK(r.detection.refractory_seconds == 1.5f);
  CHECK(r.normalisation.mean == m.normalisation.mean);
  CHECK(r.normalisation.inv_std == 0.25f);
  CHECK(r.scales.dense == 0.13f);
  CHECK_FALSE(r.quantized.has_value());
  auto a = m.network.layers();
  auto b = r.network.layers();
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i]->weights == b[i]->weights);
    CHECK(a[i]->bias == b[i]->bias);
  }
}

TEST_CASE("int8 model round trip keeps the integers and scales, and is small") {
  const kws::KwsModel m = sample_model();
  const auto bytes = kws::serialize_model(m, kws::WeightType::int8);
  CHECK(bytes.size() < 300 * 1024);
  const kws::KwsModel r = kws::parse_model(bytes, "mem");
  REQUIRE(r.quantized.has_value());
  const kws::QuantizedNetwork q = m.int8_network();
  auto a = q.layers();
  auto b = r.quantized->layers();
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i]->weights == b[i]->weights);
    CHECK(a[i]->weight_scales == b[i]->weight_scales);
  }
  // Saving the loaded model again gives the same bytes.
  CHECK(kws::serialize_model(r, kws::WeightType::int8) == bytes);
  // And through a real file.
  const auto path = std::filesystem::temp_directory_path() / "marvin_kws_model_test.bin";
  kws::save_model(path, m, kws::WeightType::int8);
  CHECK(kws::load_model(path).quantized->conv2.weights == q.conv2.weights);
  std::filesystem::remove(path);
}

TEST_CASE("bad files are rejected with the field and the byte") {
  const auto good = kws::serialize_model(sample_model(), kws::WeightType::int8);

  SUBCASE("missing file") {
    CHECK_THROWS_WITH_AS(kws::load_model("/nonexistent/marvin.bin"),
                         doctest::Contains("cannot open"), kws::ModelFileError);
  }
  SUBCASE("not a model") {
    std::vector<std::uint8_t> b(good);
    b[0] = 'R';
    b[1] = 'I';
    CHECK(load_error(b).find("not a Marvin keyword model (bad magic at byte 0") != std::string::npos);
  }
  SUBCASE("empty file") { CHECK(load_error({}).find("truncated") != std::string::npos); }
  SUBCASE("newer version") {
    std::vector<std::uint8_t> b(good);
    put_u32(b, 8, 2);
    CHECK(load_error(b).find("format version 2 is not supported (this build reads version 1)") != std::string::npos);
  }
  SUBCASE("unknown weight type") {
    std::vector<std::uint8_t> b(good);
    put_u32(b, 12, 7);
    CHECK(load_error(b).find("weight type 7 is unknown") != std::string::npos);
  }
  SUBCASE("truncated in the weights") {
    std::vector<std::uint8_t> b(good.begin(), good.begin() + 100000);
    const std::string e = load_error(b);
    CHECK(e.find("truncated: file ends inside conv2 weights") != std::string::npos);
    CHECK(e.find("test.bin") != std::string::npos);
  }
  SUBCASE("a flipped bit") {
    std::vector<std::uint8_t> b(good);
    b[50000] ^= 0x10;
    CHECK(load_error(b).find("checksum mismatch") != std::string::npos);
  }
  SUBCASE("features from another front end") {
    std::vector<std::uint8_t> b(good);
    put_u32(b, 32, 20);  // num_bins
    fix_crc(b);
    CHECK(load_error(b).find("features.num_bins is 20 but this build's log-mel features use 40") != std::string::npos);
  }
  SUBCASE("wrong layer shape") {
    kws::KwsModel m = sample_model();
    std::vector<std::uint8_t> b = kws::serialize_model(m, kws::WeightType::float32);
    // First layer's `out` follows the header, the keyword, the normalisation and the scales.
    const std::size_t at = 80 + 6 + 4 * 41 + 4 * 5;
    std::uint32_t out = 0;
    std::memcpy(&out, b.data() + at, 4);
    REQUIRE(out == 64);
    put_u32(b, at, 32);
    fix_crc(b);
    CHECK(load_error(b).find("layer conv1 is 32x160, the architecture needs 64x160") != std::string::npos);
  }
  SUBCASE("not a number") {
    std::vector<std::uint8_t> b(good);
    const float nan = std::nanf("");
    std::memcpy(b.data() + 64, &nan, 4);  // detection.threshold
    fix_crc(b);
    CHECK(load_error(b).find("detection.threshold is not a finite number (at byte 64)") != std::string::npos);
  }
  SUBCASE("the good bytes load") { CHECK(load_error(good) == "no error"); }
}
