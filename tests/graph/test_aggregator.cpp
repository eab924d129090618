#include <doctest/doctest.h>

#include <vector>

#include "graph/aggregator.h"
#include "graph/graph.h"
#include "test_nodes.h"

using namespace marvin::graph;
using testing::quiet_options;
using testing::Recorder;

namespace {

struct Window {
  int16_t first;
  int16_t last;
  std::size_t size;
  uint64_t end;  // absolute index of the last sample
};

// Feeds samples 0, 1, 2, ... in chunks of the given sizes (cycled) until `total` samples.
std::vector<Window> run(SlidingWindow& w, const std::vector<std::size_t>& sizes, std::size_t total) {
  std::vector<Window> out;
  std::size_t next = 0;
  for (std::size_t k = 0; next < total; ++k) {
    const std::size_t n = std::min(sizes[k % sizes.size()], total - next);
    std::vector<int16_t> chunk(n);
    for (std::size_t i = 0; i < n; ++i) chunk[i] = static_cast<int16_t>((next + i) % 32768);
    w.add(chunk.data(), n, [&](const std::vector<int16_t>& win, std::size_t last) {
      out.push_back({win.front(), win.back(), win.size(), next + last});
    });
    next += n;
  }
  return out;
}

}  // namespace

TEST_CASE("windows are exact for any chunk sizes") {
  for (const auto& sizes : std::vector<std::vector<std::size_t>>{
           {1}, {3}, {7}, {10}, {13}, {3, 7, 1, 13, 2}, {40}, {4}}) {
    CAPTURE(sizes);
    SlidingWindow w(10, 4);
    const std::vector<Window> got = run(w, sizes, 50);
    // Windows end at samples 9, 13, 17, ..., 49: (50 - 10) / 4 + 1 = 11 of them.
    REQUIRE(got.size() == 11);
    for (std::size_t k = 0; k < got.size(); ++k) {
      CHECK(got[k].size == 10);
      CHECK(got[k].first == static_cast<int16_t>(4 * k));
      CHECK(got[k].last == static_cast<int16_t>(4 * k + 9));
      CHECK(got[k].end == 4 * k + 9);
    }
    CHECK(w.samples_seen() == 50);
    CHECK(w.windows_emitted() == 11);
  }
}

TEST_CASE("1000 ms windows every 250 ms at 16 kHz from 333-sample chunks") {
  SlidingWindow w(16000, 4000);
  const std::vector<Window> got = run(w, {333}, 48000);
  REQUIRE(got.size() == 1 + (48000 - 16000) / 4000);
  for (std::size_t k = 0; k < got.size(); ++k) {
    CHECK(got[k].end == 16000 + 4000 * k - 1);
    CHECK(got[k].first == static_cast<int16_t>((4000 * k) % 32768));
  }
}

TEST_CASE("reset forgets the partial window") {
  SlidingWindow w(10, 5);
  std::vector<int16_t> six(6, 1);
  int windows = 0;
  w.add(six.data(), six.size(), [&](const auto&, std::size_t) { ++windows; });
  w.reset();
  w.add(six.data(), six.size(), [&](const auto&, std::size_t) { ++windows; });
  CHECK(windows == 0);  // 12 samples in all, but never 10 since the reset
  std::vector<int16_t> four(4, 2);
  w.add(four.data(), four.size(), [&](const auto& win, std::size_t last) {
    ++windows;
    CHECK(last == 3);
    CHECK(win.front() == 1);
    CHECK(win.back() == 2);
  });
  CHECK(windows == 1);
  CHECK(w.samples_seen() == 16);
}

TEST_CASE("the Aggregator node stamps each window with its last sample's time") {
  GraphConfig c;
  c.add_node("mic", "SyntheticAudioSource",
             {{"waveform", "ramp"}, {"chunk_samples", 333}, {"duration_ms", 3000}, {"pace", 0}})
      .add_node("window", "Aggregator", {{"window_ms", 1000}, {"hop_ms", 250}})
      .add_node("sink", "Sink")
      .connect("mic.out", "window.in")
      .connect("window.out", "sink.in");
  Graph g(c, quiet_options());
  Recorder seen;
  g.observe("window.out", seen.observer());
  g.start();
  g.wait();
  const std::vector<Packet> windows = seen.packets();
  REQUIRE(windows.size() == 9);
  for (std::size_t k = 0; k < windows.size(); ++k) {
    const AudioChunk& a = windows[k].get<AudioChunk>();
    CHECK(a.samples.size() == 16000);
    CHECK(a.samples.front() == static_cast<int16_t>((4000 * k) % 32768));
    const int64_t last = static_cast<int64_t>(16000 + 4000 * k - 1);
    const int64_t chunk_start = last / 333 * 333;
    CHECK(windows[k].timestamp() ==
          sample_timestamp(sample_timestamp(0, chunk_start, 16000), last - chunk_start, 16000));
  }
}

TEST_CASE("a discontinuous chunk restarts the window") {
  GraphConfig c;
  c.add_node("in", "GraphInput", {{"type", "AudioChunk"}})
      .add_node("window", "Aggregator", {{"window_ms", 10}, {"hop_ms", 5}})
      .connect("in.out", "window.in");
  Graph g(c, quiet_options());
  Recorder seen;
  g.observe("window.out", seen.observer());
  g.start();
  auto chunk = [](int n, Timestamp ts, bool gap) {
    AudioChunk a;
    a.sample_rate = 1000;  // 10 ms = 10 samples, 5 ms = 5 samples
    a.samples.assign(static_cast<std::size_t>(n), static_cast<int16_t>(ts));
    Packet p = Packet::make<AudioChunk>(std::move(a)).at(ts * 1000);
    p.set_discontinuous(gap);
    return p;
  };
  g.push("in", chunk(8, 0, false));
  g.push("in", chunk(8, 8, true));   // restart: 8 samples since
  g.push("in", chunk(2, 16, false));  // 10 since the restart: a window
  g.close_input("in");
  g.wait();
  const std::vector<Packet> windows = seen.packets();
  REQUIRE(windows.size() == 1);
  CHECK(windows[0].discontinuous());
  CHECK(windows[0].get<AudioChunk>().samples.front() == 8);
  CHECK(windows[0].timestamp() == 17'000);
}
