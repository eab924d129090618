// COCO object detection (NanoDet through core/vision/tfjs_graph.cpp) on real photos: darknet's
// data/dog.jpg and person.jpg (Debian package darknet) and face-api's demo photo sample2
// (scripts/setup); our raw outputs against tfjs's own numbers stored for dog.jpg; the table of
// names people use; what vision_look reports; broken and missing model files.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "graph/graph.h"
#include "support/child_process.h"
#include "support/files.h"
#include "support/text.h"
#include "vision/cameras.h"
#include "vision/model_files.h"
#include "vision/object_detector.h"
#include "vision/object_names.h"
#include "vision/vision_eyes.h"
#include "vision/vision_nodes.h"

namespace fs = std::filesystem;
using namespace marvin;
using namespace marvin::vision;
using marvin::test_support::contains;
using marvin::test_support::TempDir;

namespace {

fs::path darknet_photo(const char* name) {
  const fs::path p = fs::path("/usr/share/darknet/data") / name;
  REQUIRE_MESSAGE(fs::exists(p), p.string()
                                     << " is missing: install Debian's darknet (scripts/setup)");
  return p;
}

fs::path object_source_dir() {
  const char* s = std::getenv("MARVIN_SOURCE_DIR");
  REQUIRE_MESSAGE(s != nullptr, "MARVIN_SOURCE_DIR is set by ctest");
  return s;
}

std::string object_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

// The detection of class `coco` whose box holds `centre`, or null.
const DetectedObject* found_at(const std::vector<DetectedObject>& found, const std::string& coco,
                               cv::Point2f centre) {
  for (const auto& o : found) {
    if (o.coco == coco && o.box.contains(centre)) return &o;
  }
  return nullptr;
}

ObjectDetector& detector() {
  static ObjectDetector d;
  return d;
}

// What the detector finds in darknet's photo `name`.
std::vector<DetectedObject> detect_in(const char* name) {
  return detector().detect(read_photo(darknet_photo(name)));
}

// The detection of class `coco` around `centre`; the test stops when there is none.
const DetectedObject& require_at(const std::vector<DetectedObject>& found, const std::string& coco,
                                 cv::Point2f centre) {
  const DetectedObject* o = found_at(found, coco, centre);
  REQUIRE_MESSAGE(o != nullptr,
                  "no " << coco << " around (" << centre.x << ", " << centre.y << ")");
  return *o;
}

// Why loading the model at `json` fails.
std::string load_error(const fs::path& json) {
  return object_error_of([&] { ObjectDetector d(json); });
}

// A folder camera ("folder:DIR") showing darknet's photo `name`.
std::string camera_showing(const fs::path& dir, const char* name) {
  fs::create_directories(dir);
  fs::copy_file(darknet_photo(name), dir / name);
  return "folder:" + dir.string();
}

// The built `marvin` program.
std::string marvin_program() {
  return (fs::path(std::getenv("MARVIN_BUILD_DIR")) / "core/app/marvin").string();
}

// The values of `key` in a JSON list of objects.
std::vector<std::string> values_of(const nlohmann::json& list, const char* key) {
  std::vector<std::string> values;
  for (const auto& o : list) values.push_back(o[key]);
  return values;
}

bool has(const std::vector<std::string>& values, const std::string& value) {
  return std::find(values.begin(), values.end(), value) != values.end();
}

}  // namespace

TEST_CASE("NanoDet finds the bicycle, the dog and the truck of darknet's dog.jpg") {
  const auto found = detect_in("dog.jpg");  // 768x576
  // Where they are (looked at by hand): bicycle ~(125..570, 125..425), dog ~(130..310,
  // 220..540), truck ~(465..690, 75..170).
  const DetectedObject& bicycle = require_at(found, "bicycle", {340, 280});
  const DetectedObject& dog = require_at(found, "dog", {220, 380});
  const DetectedObject& truck = require_at(found, "truck", {580, 120});
  CHECK(bicycle.box.width > 350);
  CHECK(bicycle.box.width < 520);
  CHECK(dog.box.height > 250);
  CHECK(dog.box.height < 380);
  CHECK(truck.box.width > 150);
  CHECK(truck.box.height < 150);
  CHECK(bicycle.score > 0.5f);
  CHECK(bicycle.label == "bicycle");
  // Most confident first.
  CHECK(std::is_sorted(found.begin(), found.end(),
                       [](const auto& a, const auto& b) { return a.score > b.score; }));
}

TEST_CASE("NanoDet finds the person and the horse of darknet's person.jpg") {
  const auto found = detect_in("person.jpg");  // 640x424
  const DetectedObject& person = require_at(found, "person", {230, 240});
  const DetectedObject& horse = require_at(found, "horse", {500, 240});
  CHECK(person.box.height > 220);
  CHECK(person.box.width < 140);
  CHECK(horse.box.width > 150);
}

TEST_CASE("a phone in a real photo is a 'phone' (cell phone), and the people are found") {
  const fs::path p = object_source_dir() / ".cache/vision/photos/sample2.jpg";
  REQUIRE_MESSAGE(fs::exists(p), p.string() << " is missing: run scripts/setup");
  const auto found = detector().detect(read_photo(p));
  CHECK(require_at(found, "cell phone", {180, 1300}).label == "phone");
  CHECK(std::count_if(found.begin(), found.end(),
                      [](const auto& o) { return o.coco == "person"; }) >= 2);
}

TEST_CASE("our network's raw outputs on dog.jpg match the numbers tfjs computed") {
  std::ifstream in(object_source_dir() / "tests/vision/data/dog_nanodet_reference.json");
  REQUIRE(in);
  const auto reference = nlohmann::json::parse(in);
  const auto outs =
      detector().forward(ObjectDetector::to_blob(read_photo(darknet_photo("dog.jpg"))));
  REQUIRE(outs.size() == 6);
  double worst = 0;
  for (std::size_t k = 0; k < 6; ++k) {
    const auto& r = reference["outputs"][k];
    const cv::Mat& m = outs[k];
    const int c = m.size[1], cells = m.size[2] * m.size[3];
    const auto step = r["step"].get<int>();
    double scale = 0, diff = 0;
    for (int i = 0; i < 100; ++i) {
      // The graph's layout is [cells, C]; ours [C, cells].
      const int at = i * step, cell = at / c, channel = at % c;
      const double want = r["values"][static_cast<std::size_t>(i)].get<double>();
      scale = std::max(scale, std::abs(want));
      diff = std::max(diff, std::abs(want - m.ptr<float>()[channel * cells + cell]));
    }
    worst = std::max(worst, diff / scale);
  }
  CHECK(worst < 1e-4);
}

TEST_CASE("the names people use for COCO classes, both ways") {
  CHECK(coco_name(0) == "person");
  CHECK(coco_name(67) == "cell phone");
  CHECK(coco_name(79) == "toothbrush");
  CHECK(contains(object_error_of([] { coco_name(80); }), "expected 0..79"));
  CHECK(spoken_name("cell phone") == "phone");
  CHECK(spoken_name("remote") == "remote control");
  CHECK(spoken_name("tv") == "television");
  CHECK(spoken_name("dining table") == "table");
  CHECK(spoken_name("cup") == "cup");
  CHECK(spoken_plural("cup") == "cups");
  CHECK(spoken_plural("person") == "people");
  CHECK(spoken_plural("knife") == "knives");
  CHECK(spoken_plural("glass") == "glasses");
  CHECK(spoken_plural("scissors") == "scissors");
  CHECK(with_article("apple") == "an apple");
  CHECK(with_article("phone") == "a phone");
  CHECK(coco_class_for("phone") == "cell phone");
  CHECK(coco_class_for("Mobile") == "cell phone");
  CHECK(coco_class_for("phones") == "cell phone");
  CHECK(coco_class_for("telly") == "tv");
  CHECK(coco_class_for("TV") == "tv");
  CHECK(coco_class_for("remote control") == "remote");
  CHECK(coco_class_for("table") == "dining table");
  CHECK(coco_class_for("chairs") == "chair");
  CHECK(coco_class_for("keys") == std::nullopt);
  CHECK(coco_class_for("glass") == "wine glass");
  CHECK(coco_class_for("wine glasses") == "wine glass");
  CHECK(coco_class_for("glasses") == std::nullopt);  // spectacles
  CHECK(coco_class_for("reading glasses") == std::nullopt);
  const auto words = object_words();
  for (const char* w : {"phone", "remote control", "television", "tv", "table", "cup", "bottle"}) {
    CHECK_MESSAGE(has(words, w), w);
  }
  for (const auto& w : words) CHECK_MESSAGE(coco_class_for(w).has_value(), w);
}

TEST_CASE("vision_look reports the COCO things in view with the names people use") {
  TempDir dir;
  VisionEyes eyes(camera_showing(dir / "camera", "dog.jpg"), nullptr, dir / "photos");
  const auto seen = nlohmann::json::parse(eyes.look_json());
  CHECK(seen["width"] == 768);
  const auto labels = values_of(seen["objects"], "label");
  CHECK(has(labels, "bicycle"));
  CHECK(has(labels, "dog"));
  REQUIRE(!labels.empty());
  const auto& first = seen["objects"][0];
  CHECK(first["class"] == "bicycle");
  CHECK(first["box"].size() == 4);
  CHECK(first["score"].get<double>() > 0.5);
}

TEST_CASE("missing, truncated and wrong object models are errors naming the file") {
  TempDir dir;
  const std::string missing = load_error(dir / "nanodet.json");
  CHECK(contains(missing, (dir / "nanodet.json").string()));
  CHECK(contains(missing, "scripts/setup"));

  const fs::path model = find_model(kNanoDetModel);
  fs::copy_file(model, dir / "nanodet.json");
  const std::string no_weights = load_error(dir / "nanodet.json");
  CHECK(contains(no_weights, (dir / "nanodet.bin").string()));
  CHECK(contains(no_weights, "scripts/setup"));

  {
    std::ifstream in(model.parent_path() / "nanodet.bin", std::ios::binary);
    std::string data(1'000'000, '\0');
    in.read(data.data(), static_cast<std::streamsize>(data.size()));
    std::ofstream(dir / "nanodet.bin", std::ios::binary).write(data.data(), in.gcount());
  }
  const std::string cut = load_error(dir / "nanodet.json");
  CHECK(contains(cut, "truncated"));
  CHECK(contains(cut, "nanodet.json"));

  // An operator the loader does not know is named with its node.
  fs::copy_file(model.parent_path() / "nanodet.bin", dir / "nanodet.bin",
                fs::copy_options::overwrite_existing);
  std::ifstream in(model);
  auto graph = nlohmann::json::parse(in);
  for (auto& node : graph["modelTopology"]["node"]) {
    if (node["name"] == "PartitionedCall/onnx_tf_prefix_LeakyRelu_1") node["op"] = "Elu";
  }
  std::ofstream(dir / "nanodet.json") << graph.dump();
  const std::string op = load_error(dir / "nanodet.json");
  CHECK(contains(op, "PartitionedCall/onnx_tf_prefix_LeakyRelu_1"));
  CHECK(contains(op, "Elu"));

  std::ofstream(dir / "nanodet.json") << "{\"modelTopology\": ";
  CHECK(contains(load_error(dir / "nanodet.json"), "is not a TF.js model.json"));
}

TEST_CASE("a real photo runs through the object detector graph node") {
  register_vision_nodes();
  TempDir dir;
  graph::GraphConfig config;
  config.add_node("camera", "CameraSource",
                  {{"camera", camera_showing(dir.path(), "person.jpg")}});
  config.add_node("objects", "ObjectDetectorNode", {{"min_score", 0.4}});
  config.add_node("log", "ObjectLogger");
  config.connect("camera.frames", "objects.in");
  config.connect("objects.out", "log.in");
  graph::Graph g(config);
  std::vector<ObjectList> seen;
  g.observe("objects.out", [&](const graph::Packet& p) { seen.push_back(p.get<ObjectList>()); });
  g.start();
  g.wait();
  REQUIRE(seen.size() == 1);
  require_at(seen[0].objects, "person", {230, 240});
  require_at(seen[0].objects, "horse", {500, 240});
  for (const auto& o : seen[0].objects) CHECK(o.score >= 0.4f);
}

TEST_CASE("run --sim: \"what do you see?\" names the bicycle in front of the robot") {
  // The default home: the robot starts in the hall facing the bicycle (darknet's photo,
  // examples/worlds/photos); the simulated camera renders it and NanoDet finds it.
  TempDir dir;
  fs::create_directories(dir / "skills");
  test_support::ChildProcess p({marvin_program(), "run", "--sim", "--in-memory", "--skills-dir",
                                (dir / "skills").string(), "--world",
                                (object_source_dir() / "examples/worlds/home.json").string()});
  p.wait_for_line("Marvin: Hello, I'm Marvin.");
  p.send_line("what do you see");
  const std::string answer = p.wait_for_line_containing("Marvin: I ");
  CHECK(answer == "Marvin: I see a bicycle.");
  CHECK(test_support::exit_code(p.finish()) == 0);
}

TEST_CASE("marvin vision look PHOTO prints the objects with the faces") {
  TempDir dir;
  test_support::ChildProcess p({marvin_program(), "vision", "look",
                                darknet_photo("dog.jpg").string(), "--data-dir",
                                (dir / "data").string()});
  REQUIRE(test_support::exit_code(p.finish()) == 0);
  const auto line = nlohmann::json::parse(p.output());
  REQUIRE(line["objects"].is_array());
  const auto classes = values_of(line["objects"], "class");
  for (const char* want : {"bicycle", "dog", "truck"}) CHECK_MESSAGE(has(classes, want), want);
  CHECK(line["faces"].is_array());
}

TEST_CASE("the faces skill's grammar hears every COCO thing by the name Marvin says") {
  std::ifstream in(object_source_dir() / "skills-builtin/faces/skill.json");
  REQUIRE(in);
  const auto manifest = nlohmann::json::parse(in);
  std::vector<std::string> heard;
  for (const auto& intent : manifest["intents"]) {
    if (intent["name"] != "is_there") continue;
    for (const auto& v : intent["slots"][0]["values"]) heard.push_back(v);
  }
  std::vector<std::string> said;
  for (int i = 0; i < kCocoClasses; ++i) said.push_back(spoken_name(coco_name(i)));
  std::sort(said.begin(), said.end());
  said.erase(std::unique(said.begin(), said.end()), said.end());
  std::sort(heard.begin(), heard.end());
  CHECK(heard == said);
}
