// Helpers shared by the firmware tests: frame comparison and a sample of valid frames.
#pragma once

#include <cstring>
#include <random>
#include <vector>

#include "protocol/marvin_protocol.h"

namespace marvin::fwtest {

inline bool same_frame(const mv_frame& a, const mv_frame& b) {
  return a.type == b.type && a.len == b.len && std::memcmp(a.payload, b.payload, a.len) == 0;
}

inline mv_frame loco(std::uint8_t dir, std::uint8_t speed) {
  mv_frame f{};
  f.type = MV_LOCOMOTION;
  f.len = 2;
  f.payload[0] = dir;
  f.payload[1] = speed;
  return f;
}

inline mv_frame ext(std::uint8_t type, std::vector<std::uint8_t> payload) {
  mv_frame f{};
  f.type = type;
  f.len = static_cast<std::uint8_t>(payload.size());
  for (std::size_t i = 0; i < payload.size(); ++i) f.payload[i] = payload[i];
  return f;
}

// One frame of every type, with varied payloads.
inline std::vector<mv_frame> sample_frames() {
  return {loco(MV_LEFT_FORWARD, 200),
          loco(MV_RIGHT_FORWARD, 200),
          ext(MV_HEAD_TILT, {64 + 20}),
          ext(MV_SONAR_SWEEP, {MV_SWEEP_ON, 0, 120, 10}),
          loco(MV_LEFT_BACKWARD, 0x5A),
          ext(MV_LEDS, {MV_LED_GREEN}),
          loco(MV_RIGHT_BACKWARD, 255),
          ext(MV_CONFIG, {0x02, 0x2C, 0x02, 0x2C}),
          ext(MV_PING, {}),
          ext(MV_STOP_ALL, {}),
          loco(MV_LEFT_FORWARD, 0),
          ext(MV_SONAR_READING, {60, 0, 0x0F, 0x1F, 0x01, 0x02, 0x03, 0x04}),
          ext(MV_ACK, {MV_HEAD_TILT, 84}),
          ext(MV_FAULT, {MV_FAULT_OBSTACLE, 0x02, 0x10, 0x7F, 0x00, 0x55, 0x2A}),
          ext(MV_STATUS, {0x01, 0x7F, 0x00, 0x10, 64, 1, 0, 3, 0x11, 0x22, 0x33, 0x44}),
          loco(MV_RIGHT_FORWARD, 1)};
}

// Encodes frames back to back; END after every `end_every` frames (0: only at the end).
inline std::vector<std::uint8_t> encode_stream(const std::vector<mv_frame>& frames,
                                               std::size_t end_every = 0) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    std::uint8_t buf[MV_MAX_FRAME];
    std::size_t n = mv_encode_frame(&frames[i], buf);
    out.insert(out.end(), buf, buf + n);
    if (end_every && (i + 1) % end_every == 0) out.push_back(MV_END);
  }
  out.push_back(MV_END);
  return out;
}

inline std::vector<mv_frame> decode_stream(const std::vector<std::uint8_t>& bytes,
                                           mv_decoder* dec_out = nullptr) {
  mv_decoder d;
  mv_decoder_init(&d);
  std::vector<mv_frame> frames;
  for (std::uint8_t b : bytes) {
    mv_frame f;
    if (mv_decoder_push(&d, b, &f)) frames.push_back(f);
  }
  mv_frame f;
  if (mv_decoder_idle(&d, &f)) frames.push_back(f);
  if (dec_out) *dec_out = d;
  return frames;
}

// True if `got` appears in order within `sent` (nothing invented, nothing reordered).
inline bool is_subsequence(const std::vector<mv_frame>& got, const std::vector<mv_frame>& sent) {
  std::size_t j = 0;
  for (const mv_frame& g : got) {
    while (j < sent.size() && !same_frame(g, sent[j])) ++j;
    if (j == sent.size()) return false;
    ++j;
  }
  return true;
}

}  // namespace marvin::fwtest
