// Graph nodes of the voice loop (core/graph), registered by name for graphs in JSON
// (graphs/voice_loop.json):
//
//   AudioFileSource    -> out (AudioChunk)
//       path (required): WAV/FLAC, any rate, converted to 16 kHz mono;
//       chunk_ms (20); pace (0 = as fast as possible, 1.0 = real time, 2.0 = twice as fast)
//   LogMelFeatures     in (AudioChunk) -> out (LogMelFrames): 40 x 25 ms / 10 ms frames
//   WakeWordAttention  in (AudioChunk) -> listening (bool), an AttentionNode
//       true from the end of the wake word until the end of speech (trailing silence) or the
//       timeout; drives the Latch in front of the recognizer (and the status light: red while
//       false, green while true).
//       sensitivity (0.5), trailing_silence_ms (400), no_speech_timeout_ms (5000)
//   SpeechRecognizerNode  audio (AudioChunk, the latched stream), listening (bool)
//       -> utterance (Recognition): one result per listening period, emitted at its end.
//       grammar_file (""; empty = a small demo grammar), rejection_threshold (-3)
//   EchoReply          in (Recognition) -> out (string): "You said: ..." / the no-match
//       answer; stands where the interpreter and skill manager go in the host.
//   SpeechSynthesisNode  in (string) -> out (AudioChunk): the reply, stamped from the
//       timestamp of the text on; voice ("en-us"), rate (160)
//   AudioFileSink      in (AudioChunk): writes what it received to `path` (16 kHz WAV) at
//       close, placed by timestamp (gaps filled with silence), so the file shows when each
//       reply started relative to the input.
//
// The nodes live in the static library marvin_perception: call register_voice_nodes() once
// before building a graph that uses them (static registration objects in an unreferenced
// archive member would be dropped by the linker).
#pragma once

#include <cstdint>
#include <vector>

#include "graph/node_registry.h"
#include "graph/packet.h"
#include "perception/speech_recognizer.h"

namespace marvin::perception {

// A run of log-mel frames: frame f of the stream covers samples [f*160, f*160+400).
struct LogMelFrames {
  std::int64_t first_frame = 0;
  int num_bins = 40;
  std::vector<float> values;  // frames x num_bins, row-major
};

// Adds the node types above to `registry` (the global one by default). Idempotent.
void register_voice_nodes(graph::NodeRegistry& registry = graph::NodeRegistry::global());

}  // namespace marvin::perception

MARVIN_PACKET_TYPE(marvin::perception::LogMelFrames, "LogMelFrames");
MARVIN_PACKET_TYPE(marvin::perception::Recognition, "Recognition");
