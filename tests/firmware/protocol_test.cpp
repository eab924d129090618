// The shared protocol: round trips, error detection, resynchronisation, the random bound.
#include <doctest/doctest.h>

#include <cstdio>

#include "frames.h"

using namespace marvin::fwtest;

TEST_CASE("every locomotion frame round-trips, and exactly 2^10 of 2^16 words are valid") {
  for (unsigned dir = 0; dir < 4; ++dir) {
    for (unsigned speed = 0; speed < 256; ++speed) {
      std::uint8_t buf[MV_MAX_FRAME];
      REQUIRE(mv_encode_locomotion(static_cast<std::uint8_t>(dir), static_cast<std::uint8_t>(speed),
                                   buf) == 2);
      CHECK((buf[0] & 0xC0) == 0x80);
      CHECK((buf[1] & 0x80) == 0);
      auto got = decode_stream({buf[0], buf[1]});
      REQUIRE(got.size() == 1);
      CHECK(same_frame(got[0],
                       loco(static_cast<std::uint8_t>(dir), static_cast<std::uint8_t>(speed))));
    }
  }
  // The 6 integrity bits: exactly one word in 64 decodes.
  int valid = 0;
  for (unsigned w = 0; w < 65536; ++w) {
    auto got =
        decode_stream({static_cast<std::uint8_t>(w >> 8), static_cast<std::uint8_t>(w & 0xFF)});
    valid += static_cast<int>(got.size());
  }
  CHECK(valid == 1024);
}

TEST_CASE("every frame type round-trips, with and without END between frames") {
  auto frames = sample_frames();
  for (std::size_t end_every : {0, 1, 3}) {
    auto got = decode_stream(encode_stream(frames, end_every));
    REQUIRE(got.size() == frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) CHECK(same_frame(got[i], frames[i]));
  }
  // Fields wider than 7 bits.
  std::uint8_t p[4];
  mv_put14(p, 0x3ABC);
  CHECK(mv_get14(p) == 0x3ABC);
  mv_put28(p, 0x0ABCDEF1);
  CHECK(mv_get28(p) == 0x0ABCDEF1);
}

TEST_CASE("encoders refuse out-of-range arguments") {
  std::uint8_t buf[MV_MAX_FRAME];
  CHECK(mv_encode_locomotion(4, 10, buf) == 0);
  std::uint8_t bad[1] = {0x80};
  CHECK(mv_encode_ext(MV_HEAD_TILT, bad, 1, buf) == 0);  // not a 7-bit byte
  CHECK(mv_encode_ext(MV_HEAD_TILT, bad, 0, buf) == 0);  // wrong length
  CHECK(mv_encode_ext(0x15, bad, 0, buf) == 0);          // unknown type
}

TEST_CASE("every single-bit flip is rejected or resynchronised, never executed wrongly") {
  auto frames = sample_frames();
  for (std::size_t end_every : {0, 1, 4}) {
    auto stream = encode_stream(frames, end_every);
    for (std::size_t i = 0; i < stream.size(); ++i) {
      for (int bit = 0; bit < 8; ++bit) {
        auto bad = stream;
        bad[i] = static_cast<std::uint8_t>(bad[i] ^ (1u << bit));
        auto got = decode_stream(bad);
        INFO("byte " << i << " bit " << bit << " end_every " << end_every);
        CHECK(is_subsequence(got, frames));
      }
    }
  }
}

TEST_CASE("every dropped byte and every inserted byte value is rejected or resynchronised") {
  auto frames = sample_frames();
  for (std::size_t end_every : {0, 1}) {
    auto stream = encode_stream(frames, end_every);
    for (std::size_t i = 0; i < stream.size(); ++i) {
      auto dropped = stream;
      dropped.erase(dropped.begin() + static_cast<std::ptrdiff_t>(i));
      INFO("drop byte " << i);
      CHECK(is_subsequence(decode_stream(dropped), frames));
    }
    for (std::size_t i = 0; i <= stream.size(); ++i) {
      for (unsigned v = 0; v < 256; ++v) {
        auto inserted = stream;
        inserted.insert(inserted.begin() + static_cast<std::ptrdiff_t>(i),
                        static_cast<std::uint8_t>(v));
        auto got = decode_stream(inserted);
        INFO("insert " << v << " at " << i);
        CHECK(is_subsequence(got, frames));
      }
    }
    // After the damage, the decoder resynchronises: the frames after the next END arrive.
    auto damaged = stream;
    damaged.insert(damaged.begin() + 1, std::uint8_t{0x33});
    auto tail = encode_stream({loco(MV_LEFT_FORWARD, 99)});
    damaged.insert(damaged.end(), tail.begin(), tail.end());
    auto got = decode_stream(damaged);
    REQUIRE(!got.empty());
    CHECK(same_frame(got.back(), loco(MV_LEFT_FORWARD, 99)));
  }
}

TEST_CASE("a long random byte stream executes at most N/128 frames (the stated bound)") {
  std::mt19937 rng(12345);
  const std::size_t n = 1u << 20;
  std::vector<std::uint8_t> bytes(n);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng() & 0xFF);
  mv_decoder d;
  auto got = decode_stream(bytes, &d);
  std::size_t loco_count = 0;
  for (const auto& f : got) loco_count += f.type == MV_LOCOMOTION;
  std::printf("random stream: %zu bytes, %zu frames accepted (%zu locomotion), bound %zu\n", n,
              got.size(), loco_count, n / 128);
  CHECK(got.size() <= n / 128);
  // Without the sync rule the 2^-7 per position would be reached; with it, far fewer pass.
  CHECK(got.size() <= n / 1024);
}

TEST_CASE("garbage never leaves the decoder stuck") {
  std::mt19937 rng(7);
  std::vector<std::uint8_t> bytes(4096);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng() & 0x7F);  // all continuation bytes
  auto frame = encode_stream({loco(MV_RIGHT_FORWARD, 42)});
  bytes.push_back(MV_END);
  bytes.insert(bytes.end(), frame.begin(), frame.end());
  auto got = decode_stream(bytes);
  REQUIRE(got.size() == 1);
  CHECK(same_frame(got[0], loco(MV_RIGHT_FORWARD, 42)));
}
