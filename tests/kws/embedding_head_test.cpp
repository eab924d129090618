// The embedding wake word's head: file round trip and refusal of bad files, training on a toy
// problem, determinism for a seed.
#include "perception/kws/embedding_head.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "kws/training/head_trainer.h"
#include "perception/kws/model_file.h"

namespace kws = marvin::perception::kws;

namespace {

kws::EmbeddingHead numbered_head() {
  kws::EmbeddingHead h;
  h.keyword = "smart mirror";
  h.threshold = 0.8f;
  h.refractory_seconds = 1.5f;
  h.consecutive = 3;
  h.resize(8);
  float v = 0.0f;
  for (auto* w : {&h.w1, &h.b1, &h.w2, &h.b2, &h.w3}) {
    for (float& x : *w) x = (v += 0.001f);
  }
  h.b3 = -0.5f;
  return h;
}

std::string head_error(const std::vector<std::uint8_t>& bytes) {
  try {
    kws::parse_head(bytes, "head.bin");
  } catch (const kws::ModelFileError& e) {
    return e.what();
  }
  return "";
}

// Toy problem: noise everywhere, and embedding 12 (of 16) shifted up for positives, down for
// negatives, as a keyword that shows in the embeddings just before its end.
kws::HeadSet toy_set(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  kws::HeadSet set;
  std::vector<float> x(kws::kHeadInputs);
  for (std::size_t k = 0; k < n; ++k) {
    const bool positive = (rng() & 1u) != 0;
    for (float& v : x) v = noise(rng);
    for (int d = 0; d < kws::kEmbeddingSize; ++d)
      x[12 * kws::kEmbeddingSize + d] += positive ? 0.25f : -0.25f;
    set.add(x, positive ? 1.0f : 0.0f);
  }
  return set;
}

}  // namespace

TEST_CASE("an embedding head file round-trips") {
  const kws::EmbeddingHead h = numbered_head();
  const auto path = std::filesystem::temp_directory_path() / "marvin-head-roundtrip.bin";
  kws::save_head(path, h);
  const kws::EmbeddingHead back = kws::load_head(path);
  CHECK(back.keyword == "smart mirror");
  CHECK(back.hidden == 8);
  CHECK(back.threshold == 0.8f);
  CHECK(back.refractory_seconds == 1.5f);
  CHECK(back.consecutive == 3);
  CHECK(back.w1 == h.w1);
  CHECK(back.w2 == h.w2);
  CHECK(back.w3 == h.w3);
  CHECK(back.b1 == h.b1);
  CHECK(back.b2 == h.b2);
  CHECK(back.b3 == h.b3);
  std::vector<float> input(kws::kHeadInputs, 0.1f);
  CHECK(back.score(input) == h.score(input));
  std::filesystem::remove(path);
}

TEST_CASE("a version 1 head file (no consecutive steps) still loads, needing one step") {
  // Version 1 is version 2 without the u32 at byte 32.
  std::vector<std::uint8_t> bytes = kws::serialize_head(numbered_head());
  bytes.erase(bytes.begin() + 32, bytes.begin() + 36);
  bytes[8] = 1;
  bytes.resize(bytes.size() - 4);
  const std::uint32_t crc = kws::crc32(bytes.data(), bytes.size());
  const auto* p = reinterpret_cast<const std::uint8_t*>(&crc);
  bytes.insert(bytes.end(), p, p + 4);
  const kws::EmbeddingHead back = kws::parse_head(bytes, "v1.bin");
  CHECK(back.consecutive == 1);
  CHECK(back.keyword == "smart mirror");
  CHECK(back.refractory_seconds == 1.5f);
  CHECK(back.w1 == numbered_head().w1);
  CHECK(back.b3 == -0.5f);
}

TEST_CASE("bad embedding head files are refused with the field and byte") {
  const std::vector<std::uint8_t> good = kws::serialize_head(numbered_head());
  CHECK(head_error(good).empty());

  auto truncated = good;
  truncated.resize(good.size() - 100);
  const std::string t = head_error(truncated);
  CHECK(t.find("head.bin: weights") != std::string::npos);
  CHECK(t.find("truncated") != std::string::npos);

  const std::string tiny = head_error(std::vector<std::uint8_t>(good.begin(), good.begin() + 20));
  CHECK(tiny.find("truncated") != std::string::npos);

  auto version = good;
  version[8] = 7;
  CHECK(head_error(version).find(
            "version at byte 12: format version 7, this build reads 1 and 2") != std::string::npos);

  auto magic = good;
  magic[0] = 'X';
  CHECK(head_error(magic).find("magic at byte 0") != std::string::npos);

  auto cnn = good;
  std::memcpy(cnn.data(), "MRVNKWS", 8);  // the CNN spotter's file is not a head
  CHECK(head_error(cnn).find("MRVNKWE") != std::string::npos);

  auto flipped = good;
  flipped[good.size() / 2] ^= 0x40;
  CHECK(head_error(flipped).find("checksum") != std::string::npos);

  auto frames = good;
  frames[12] = 10;
  CHECK(head_error(frames).find("embeddings per input at byte 16: 10, expected 16") !=
        std::string::npos);

  auto steps = good;
  steps[32] = 0;
  CHECK(head_error(steps).find("consecutive steps at byte 36: 0, expected 1..10") !=
        std::string::npos);

  CHECK_THROWS_WITH_AS(kws::load_head("/nonexistent/head.bin"),
                       doctest::Contains("/nonexistent/head.bin"), kws::ModelFileError);
}

TEST_CASE("head training learns a toy problem and is deterministic for a seed") {
  const kws::HeadSet train = toy_set(1500, 1);
  const kws::HeadSet test = toy_set(500, 2);
  kws::HeadTrainOptions options;
  options.hidden = 16;
  options.epochs = 8;
  options.batch = 64;
  options.learning_rate = 3e-3f;
  options.seed = 5;
  const kws::EmbeddingHead untrained = [&] {
    kws::HeadTrainOptions none = options;
    none.epochs = 0;
    return kws::train_head(train, none);
  }();
  const kws::HeadAccuracy before = kws::head_accuracy(untrained, test, 0.5f);
  const kws::EmbeddingHead head = kws::train_head(train, options);
  const kws::HeadAccuracy after = kws::head_accuracy(head, test, 0.5f);
  MESSAGE("toy accuracy before ", before.positives, "/", before.negatives, " after ",
          after.positives, "/", after.negatives);
  CHECK(after.positives > 0.9);
  CHECK(after.negatives > 0.9);
  CHECK(after.positives + after.negatives > before.positives + before.negatives + 0.3);
  const kws::EmbeddingHead again = kws::train_head(train, options);
  CHECK(again.w1 == head.w1);
  CHECK(again.b3 == head.b3);
  options.seed = 6;
  CHECK(kws::train_head(train, options).w1 != head.w1);
}

TEST_CASE("merged heads score the sigmoid of the members' mean logit; mismatches are refused") {
  std::mt19937_64 rng(21);
  std::normal_distribution<float> small(0.0f, 0.05f);
  auto random_head = [&](int hidden) {
    kws::EmbeddingHead h;
    h.resize(hidden);
    for (auto* w : {&h.w1, &h.b1, &h.w2, &h.b2, &h.w3}) {
      for (float& x : *w) x = small(rng);
    }
    h.b3 = small(rng) * 20.0f;
    return h;
  };
  std::vector<kws::EmbeddingHead> members = {random_head(8), random_head(5), random_head(8)};
  members.front().threshold = 0.9f;
  members.front().consecutive = 3;
  const kws::EmbeddingHead merged = kws::merge_heads(members);
  CHECK(merged.hidden == 21);
  CHECK(merged.keyword == "marvin");
  CHECK(merged.threshold == 0.9f);
  CHECK(merged.consecutive == 3);
  auto logit = [](float p) { return std::log(p / (1.0f - p)); };
  std::normal_distribution<float> input(0.0f, 1.0f);
  std::vector<float> x(kws::kHeadInputs);
  for (int trial = 0; trial < 5; ++trial) {
    for (float& v : x) v = input(rng);
    float mean = 0.0f;
    for (const auto& m : members) mean += logit(m.score(x)) / 3.0f;
    INFO("trial ", trial, ": members' mean logit ", mean);
    CHECK(logit(merged.score(x)) == doctest::Approx(mean).epsilon(1e-4));
  }
  // A merged head is an ordinary head: it round-trips through the file format.
  CHECK(kws::parse_head(kws::serialize_head(merged), "m.bin").w2 == merged.w2);

  members[1].keyword = "alexa";
  CHECK_THROWS_WITH_AS(kws::merge_heads(members),
                       "merge_heads: heads for \"marvin\" and \"alexa\" cannot be merged",
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(kws::merge_heads({random_head(600), random_head(600)}),
                       "merge_heads: 1200 hidden units together, a head holds at most 1024",
                       std::invalid_argument);
  CHECK_THROWS_AS(kws::merge_heads({}), std::invalid_argument);
}

TEST_CASE("raising the negatives' weight over the epochs trades misses for fewer false accepts") {
  // A toy set whose classes overlap: no head separates them, so the weights decide the balance.
  auto overlapping = [](std::size_t n, std::uint64_t seed) {
    kws::HeadSet set = toy_set(n, seed);
    for (std::size_t k = 0; k < set.size(); ++k) {
      const float shift = set.labels[k] > 0.5f ? 0.25f : -0.25f;
      for (int d = 0; d < kws::kEmbeddingSize; ++d) {
        // Keep a tenth of the shift: about half a standard deviation between the classes.
        set.inputs[k * kws::kHeadInputs + 12 * kws::kEmbeddingSize + static_cast<std::size_t>(d)] -=
            0.9f * shift;
      }
    }
    return set;
  };
  const kws::HeadSet train = overlapping(1500, 3);
  const kws::HeadSet test = overlapping(1000, 4);
  kws::HeadTrainOptions options;
  options.hidden = 16;
  options.epochs = 6;
  options.batch = 64;
  options.learning_rate = 3e-3f;
  const kws::HeadAccuracy flat = kws::head_accuracy(kws::train_head(train, options), test, 0.5f);
  options.final_negative_weight = 8.0f;
  const kws::HeadAccuracy raised = kws::head_accuracy(kws::train_head(train, options), test, 0.5f);
  MESSAGE("flat ", flat.positives, "/", flat.negatives, " raised ", raised.positives, "/",
          raised.negatives);
  CHECK(raised.negatives > flat.negatives + 0.05);
  CHECK(raised.positives < flat.positives);
}

TEST_CASE("a feature file round-trips and bad ones are refused, naming the file and byte") {
  const kws::HeadSet set = toy_set(5, 9);
  const auto dir = std::filesystem::temp_directory_path() / "marvin-feature-test";
  std::filesystem::create_directories(dir);
  const auto path = dir / "set.feat";
  kws::save_head_set(path, set);
  const kws::HeadSet back = kws::load_head_set(path);
  CHECK(back.labels == set.labels);
  CHECK(back.inputs == set.inputs);

  std::vector<char> bytes(std::filesystem::file_size(path));
  std::ifstream(path, std::ios::binary)
      .read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  auto write = [&](const std::vector<char>& b) {
    const auto p = dir / "bad.feat";
    std::ofstream(p, std::ios::binary | std::ios::trunc)
        .write(b.data(), static_cast<std::streamsize>(b.size()));
    return p;
  };
  auto magic = bytes;
  magic[0] = 'X';
  CHECK_THROWS_WITH_AS(kws::load_head_set(write(magic)),
                       doctest::Contains("bad.feat: bytes 0..7: expected \"MKWSFEAT\""),
                       kws::ModelFileError);
  auto version = bytes;
  version[8] = 2;
  CHECK_THROWS_WITH_AS(kws::load_head_set(write(version)),
                       doctest::Contains("byte 8: version 2, expected 1"), kws::ModelFileError);
  auto truncated = bytes;
  truncated.resize(bytes.size() - 4);
  const std::string size_error = std::to_string(bytes.size() - 4) + " bytes, expected " +
                                 std::to_string(bytes.size()) + " for 5 examples";
  CHECK_THROWS_WITH_AS(kws::load_head_set(write(truncated)), doctest::Contains(size_error.c_str()),
                       kws::ModelFileError);
  CHECK_THROWS_WITH_AS(
      kws::load_head_set(write(std::vector<char>(bytes.begin(), bytes.begin() + 12))),
      doctest::Contains("truncated header"), kws::ModelFileError);
  // The good file is untouched by the failed loads.
  CHECK(kws::load_head_set(path).inputs == set.inputs);
  std::filesystem::remove_all(dir);
}
