// marvin-kws-model, run as a process: it rewrites a model's detection defaults without
// touching a weight, and refuses bad settings without writing anything.
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "perception/kws/embedding_head.h"
#include "perception/kws/model_file.h"

namespace kws = marvin::perception::kws;
namespace fs = std::filesystem;

namespace {

struct Run {
  int status = -1;
  std::string output;  // stdout and stderr
};

Run run_tool(const std::string& args) {
  const char* build = std::getenv("MARVIN_BUILD_DIR");
  const fs::path tool = fs::path(build ? build : ".") / "tools" / "kws" / "marvin-kws-model";
  INFO(tool.string() << " must be built");
  REQUIRE(fs::exists(tool));
  Run r;
  FILE* p = popen((tool.string() + " " + args + " 2>&1").c_str(), "r");
  REQUIRE(p != nullptr);
  std::array<char, 512> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), p)) r.output += buf.data();
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("kws_model_tool_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

}  // namespace

TEST_CASE("marvin-kws-model sets the detection defaults and keeps the weights") {
  TempDir dir;
  kws::KwsModel m;
  m.network = kws::make_initialised_network(4);
  const fs::path in = dir.path / "in.bin", out = dir.path / "out.bin";
  kws::save_model(in, m, kws::WeightType::float32);

  const Run ok = run_tool(in.string() + " --threshold 0.97 --smoothing 1 --refractory 1.5 --out " +
                          out.string());
  INFO(ok.output);
  REQUIRE(ok.status == 0);
  kws::KwsModel changed = kws::load_model(out);
  CHECK(changed.detection.threshold == doctest::Approx(0.97f));
  CHECK(changed.detection.smoothing_windows == 1);
  CHECK(changed.detection.refractory_seconds == doctest::Approx(1.5f));
  const auto a = m.network.layers();
  const auto b = changed.network.layers();
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i]->weights == b[i]->weights);
    CHECK(a[i]->bias == b[i]->bias);
  }
  // Showing a model prints its settings.
  const Run show = run_tool(out.string());
  CHECK(show.status == 0);
  CHECK(show.output.find("threshold 0.970, smoothing 1 windows") != std::string::npos);
}

TEST_CASE("marvin-kws-model refuses bad settings and writes nothing") {
  TempDir dir;
  kws::KwsModel m;
  m.network = kws::make_initialised_network(5);
  const fs::path in = dir.path / "in.bin", out = dir.path / "out.bin";
  kws::save_model(in, m, kws::WeightType::float32);
  const std::string before = bytes_of(in);

  Run r = run_tool(in.string() + " --threshold 1.5 --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("--threshold 1.5") != std::string::npos);
  CHECK(r.output.find("expected a value in (0, 1)") != std::string::npos);

  r = run_tool(in.string() + " --smoothing 0 --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("--smoothing 0: expected 1..64 windows") != std::string::npos);

  r = run_tool(in.string() + " --smoothing 2");
  CHECK(r.status == 1);
  CHECK(r.output.find("need --out") != std::string::npos);

  r = run_tool((dir.path / "missing.bin").string() + " --smoothing 2 --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("missing.bin: cannot open") != std::string::npos);

  CHECK_FALSE(fs::exists(out));
  CHECK(bytes_of(in) == before);
}

TEST_CASE("marvin-kws-model sets an embedding head's threshold and steps, weights untouched") {
  TempDir dir;
  kws::EmbeddingHead h;
  h.keyword = "alexa";
  h.resize(4);
  for (std::size_t i = 0; i < h.w1.size(); ++i) h.w1[i] = 0.001f * static_cast<float>(i % 97);
  h.b3 = -0.25f;
  const fs::path in = dir.path / "head.bin", out = dir.path / "tuned.bin";
  kws::save_head(in, h);
  const Run ok = run_tool(in.string() + " --threshold 0.4 --consecutive 3 --out " + out.string());
  INFO(ok.output);
  REQUIRE(ok.status == 0);
  const kws::EmbeddingHead tuned = kws::load_head(out);
  CHECK(tuned.threshold == doctest::Approx(0.4f));
  CHECK(tuned.consecutive == 3);
  CHECK(tuned.refractory_seconds == h.refractory_seconds);
  CHECK(tuned.keyword == "alexa");
  CHECK(tuned.w1 == h.w1);
  CHECK(tuned.b3 == h.b3);
  CHECK(ok.output.find("threshold 0.400, 3 consecutive steps") != std::string::npos);
}

TEST_CASE("marvin-kws-model refuses settings that do not fit the file and writes nothing") {
  TempDir dir;
  kws::EmbeddingHead h;
  h.resize(4);
  const fs::path head = dir.path / "head.bin", cnn = dir.path / "cnn.bin",
                 out = dir.path / "out.bin";
  kws::save_head(head, h);
  kws::KwsModel m;
  m.network = kws::make_initialised_network(6);
  kws::save_model(cnn, m, kws::WeightType::float32);
  const std::string head_before = bytes_of(head), cnn_before = bytes_of(cnn);

  Run r = run_tool(head.string() + " --consecutive 0 --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("--consecutive 0: expected 1..10 steps") != std::string::npos);
  r = run_tool(head.string() + " --smoothing 2 --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("an embedding head takes --consecutive") != std::string::npos);
  r = run_tool(cnn.string() + " --consecutive 2 --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("the cnn spotter's model takes --smoothing") != std::string::npos);

  CHECK_FALSE(fs::exists(out));
  CHECK(bytes_of(head) == head_before);
  CHECK(bytes_of(cnn) == cnn_before);
}

TEST_CASE("marvin-kws-model merges embedding heads into one, and refuses what cannot be merged") {
  TempDir dir;
  auto head = [](const std::string& keyword, float scale) {
    kws::EmbeddingHead h;
    h.keyword = keyword;
    h.resize(4);
    for (std::size_t i = 0; i < h.w1.size(); ++i)
      h.w1[i] = scale * 0.001f * static_cast<float>(i % 89);
    h.w3.assign(4, scale);
    return h;
  };
  const fs::path a = dir.path / "a.bin", b = dir.path / "b.bin", other = dir.path / "alexa.bin",
                 out = dir.path / "merged.bin";
  kws::save_head(a, head("marvin", 1.0f));
  kws::save_head(b, head("marvin", -0.5f));
  kws::save_head(other, head("alexa", 1.0f));
  const Run ok = run_tool(a.string() + " " + b.string() +
                          " --threshold 0.9 --consecutive 3 --out " + out.string());
  INFO(ok.output);
  REQUIRE(ok.status == 0);
  const kws::EmbeddingHead merged = kws::load_head(out);
  CHECK(merged.hidden == 8);
  CHECK(merged.threshold == doctest::Approx(0.9f));
  CHECK(merged.consecutive == 3);
  CHECK(merged.w3 == std::vector<float>{0.5f, 0.5f, 0.5f, 0.5f, -0.25f, -0.25f, -0.25f, -0.25f});
  CHECK(ok.output.find("2 heads merged: embedding head for \"marvin\", hidden 8") !=
        std::string::npos);
  fs::remove(out);

  const std::string a_before = bytes_of(a);
  Run r = run_tool(a.string() + " " + other.string() + " --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("heads for \"marvin\" and \"alexa\" cannot be merged") != std::string::npos);
  r = run_tool(a.string() + " " + b.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("merging heads needs --out") != std::string::npos);
  kws::KwsModel m;
  m.network = kws::make_initialised_network(7);
  const fs::path cnn = dir.path / "cnn.bin";
  kws::save_model(cnn, m, kws::WeightType::float32);
  r = run_tool(a.string() + " " + cnn.string() + " --out " + out.string());
  CHECK(r.status == 1);
  CHECK(r.output.find("cnn.bin: not an embedding head; only heads can be merged") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(out));
  CHECK(bytes_of(a) == a_before);
}
