// AudioChunk: the payload for audio samples everywhere in Marvin (registered as "AudioChunk").
//
// A chunk is a run of mono samples at `sample_rate` Hz, signed 16-bit PCM as microphones
// deliver them (feature extraction converts to float itself). Chunks may have any length;
// nodes must not assume a fixed size (the Aggregator re-frames them into windows).
//
// The Packet that carries a chunk is stamped with the stream time of the chunk's *first*
// sample, in microseconds: sample i of a chunk at timestamp t is at t + i * 1e6 / sample_rate.
// A chunk flagged discontinuous follows a gap (dropped chunks, a reopened latch).
#pragma once

#include <cstdint>
#include <vector>

#include "graph/packet.h"

namespace marvin::graph {

struct AudioChunk {
  int sample_rate = 16000;
  std::vector<int16_t> samples;
};

// Stream time of sample `index` in a chunk stamped `start`, rounded down to the microsecond.
inline Timestamp sample_timestamp(Timestamp start, int64_t index, int sample_rate) {
  return start + index * 1'000'000 / sample_rate;
}

}  // namespace marvin::graph

MARVIN_PACKET_TYPE(marvin::graph::AudioChunk, "AudioChunk");
