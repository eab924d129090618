// core/vision on real photos and the real converted models (scripts/setup fetches them;
// the build converts them): detection, the embedding against face-api.js's own numbers,
// the people gallery through a real SQLite file, and bad input (corrupt photos, broken or
// missing models, cameras that vanish) with the error messages and nothing stored changed.
#include <doctest/doctest.h>

#include <condition_variable>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "support/child_process.h"
#include "common/log.h"
#include "data/sqlite_store.h"
#include "support/files.h"
#include "graph/graph.h"
#include "support/text.h"
#include "vision/cameras.h"
#include "vision/face_gallery.h"
#include "vision/face_pipeline.h"
#include "vision/model_files.h"
#include "vision/object_memory.h"
#include "vision/tensor_file.h"
#include "vision/vision_nodes.h"

namespace fs = std::filesystem;
using namespace marvin;
using namespace marvin::vision;
using marvin::test_support::contains;
using marvin::test_support::TempDir;

namespace {

fs::path source_dir() {
  const char* s = std::getenv("MARVIN_SOURCE_DIR");
  REQUIRE_MESSAGE(s != nullptr, "MARVIN_SOURCE_DIR is set by ctest");
  return s;
}

// face-api's demo photo (MIT, in the npm package; scripts/setup keeps it).
fs::path sample1() {
  const fs::path p = source_dir() / ".cache/vision/photos/sample1.jpg";
  REQUIRE_MESSAGE(fs::exists(p), p.string() << " is missing: run scripts/setup");
  return p;
}

// Where the three people of sample1 have their faces (looked at by hand).
const cv::Point2f kSample1Faces[] = {{517, 506}, {1565, 341}, {937, 557}};

bool some_box_contains(const std::vector<Face>& faces, cv::Point2f p) {
  for (const auto& f : faces) {
    if (f.box.contains(p)) return true;
  }
  return false;
}

const Face& face_at(const std::vector<Face>& faces, cv::Point2f p) {
  for (const auto& f : faces) {
    if (f.box.contains(p)) return f;
  }
  FAIL("no face at " << p.x << "," << p.y);
  return faces.front();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

void copy_prefix(const fs::path& from, const fs::path& to, std::size_t bytes) {
  std::ifstream in(from, std::ios::binary);
  std::string data(bytes, '\0');
  in.read(data.data(), static_cast<std::streamsize>(bytes));
  std::ofstream(to, std::ios::binary).write(data.data(), in.gcount());
}

data::StoreOptions store_at(const fs::path& file) {
  data::StoreOptions o;
  o.path = file;
  return o;
}

}  // namespace

TEST_CASE("BlazeFace finds the three faces of a real group photo; Haar finds the nearest one") {
  const cv::Mat image = read_photo(sample1());
  BlazeFaceDetector blaze;
  const auto faces = blaze.detect(image);
  CHECK(faces.size() == 3);
  for (const auto& p : kSample1Faces) CHECK(some_box_contains(faces, p));
  for (const auto& f : faces) {
    CHECK(f.score > 0.6f);
    CHECK(f.landmarks.size() == 6);
    CHECK(f.box.contains(f.landmarks[2]));  // the nose is inside the face
  }
  HaarFaceDetector haar;
  CHECK(some_box_contains(haar.detect(image), kSample1Faces[0]));
}

TEST_CASE("the embedding of a real face matches face-api.js's own JavaScript") {
  std::ifstream in(source_dir() / "tests/vision/data/sample1_face_api_reference.json");
  const auto ref = nlohmann::json::parse(in)["embedding"].get<std::vector<float>>();
  REQUIRE(ref.size() == 128);
  FacePipeline pipeline("blazeface");
  const auto face = pipeline.main_face(read_photo(sample1()));
  REQUIRE(face.has_value());
  float scale = 0, worst = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    scale = std::max(scale, std::abs(ref[i]));
    worst = std::max(worst, std::abs(ref[i] - face->embedding[i]));
  }
  CHECK(worst / scale < 1e-4f);
}

TEST_CASE("the same face at half the size stays close; other people are far") {
  FacePipeline pipeline("blazeface");
  const cv::Mat image = read_photo(sample1());
  cv::Mat half;
  cv::resize(image, half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  const auto big = pipeline.faces(image);
  const auto small = pipeline.faces(half);
  const cv::Point2f a = kSample1Faces[0], b = kSample1Faces[1];
  const float same = squared_distance(face_at(big, a).embedding, face_at(small, a * 0.5f).embedding);
  const float other = squared_distance(face_at(big, a).embedding, face_at(big, b).embedding);
  CHECK(same < kDefaultFaceThreshold);
  CHECK(other > kDefaultFaceThreshold);
}

TEST_CASE("enrol, identify, forget: a round trip through a real SQLite file") {
  TempDir dir;
  const fs::path db = dir / "marvin.db";
  FacePipeline pipeline("blazeface");
  const cv::Mat image = read_photo(sample1());
  cv::Mat half;
  cv::resize(image, half, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  const auto faces = pipeline.faces(image);
  const auto later = pipeline.faces(half);
  {
    data::SqliteStore store(store_at(db));
    FaceGallery gallery(store);
    gallery.enroll("Anna", {face_at(faces, kSample1Faces[0]).embedding}, "test");
    gallery.enroll("Bob", {face_at(faces, kSample1Faces[1]).embedding}, "test");
    gallery.enroll("anna", {face_at(faces, kSample1Faces[0]).embedding}, "voice:owner");
  }
  data::SqliteStore store(store_at(db));  // reopened: everything came from the file
  FaceGallery gallery(store);
  const auto people = gallery.list();
  REQUIRE(people.size() == 2);
  CHECK(people[0].name == "Anna");
  CHECK(people[0].embeddings == 2);
  CHECK(people[0].last_enrolled_by == "voice:owner");
  CHECK(people[0].last_enrolled_utc_ms > 0);
  CHECK(people[1].embeddings == 1);

  const FaceMatch anna = gallery.identify(face_at(later, kSample1Faces[0] * 0.5f).embedding);
  CHECK(anna.known);
  CHECK(anna.name == "Anna");
  const FaceMatch stranger = gallery.identify(face_at(later, kSample1Faces[2] * 0.5f).embedding);
  CHECK_FALSE(stranger.known);

  // Renaming keeps the faces; a name someone else has, or none, is refused with nothing changed.
  CHECK_THROWS_WITH(gallery.rename("Anna", "bob", "test"),
                    "new name: Bob is already enrolled; forget or rename them first");
  CHECK_THROWS_WITH(gallery.rename("Anna", "", "test"), "new name: empty; give the person's name");
  CHECK_FALSE(gallery.rename("Carol", "Dora", "test"));
  CHECK(gallery.find("Anna"));
  REQUIRE(gallery.rename("anna", "Anna Schmidt", "test"));
  CHECK_FALSE(gallery.find("Anna"));
  CHECK(gallery.identify(face_at(later, kSample1Faces[0] * 0.5f).embedding).name ==
        "Anna Schmidt");
  CHECK(store.recent_events(1).front().message == "Anna is now called Anna Schmidt");
  REQUIRE(gallery.rename("Anna Schmidt", "Anna", "test"));

  CHECK(gallery.forget("ANNA", "test"));
  CHECK_FALSE(gallery.forget("Anna", "test"));
  CHECK(store.face_embeddings().size() == 1);
  const FaceMatch after = gallery.identify(face_at(later, kSample1Faces[0] * 0.5f).embedding);
  CHECK(after.name != "Anna");
  CHECK_FALSE(after.known);
  bool logged = false;
  for (const auto& e : store.recent_events(10)) {
    logged |= e.kind == "face_forgotten" && e.source == "test" && contains(e.message, "Anna");
  }
  CHECK(logged);
}

TEST_CASE("enrolment refuses bad input and stores nothing") {
  TempDir dir;
  data::SqliteStore store(store_at(dir / "marvin.db"));
  FaceGallery gallery(store);
  CHECK(contains(error_of([&] { gallery.enroll("", {std::vector<float>(128)}, "t"); }), "name"));
  CHECK(contains(error_of([&] { gallery.enroll("Anna", {std::vector<float>(12)}, "t"); }),
                 "embeddings[0]: 12 numbers, expected 128"));
  CHECK(store.list_people().empty());
  CHECK(store.face_embeddings().empty());
}

TEST_CASE("marvin people enroll with a corrupt photo names it and changes nothing") {
  TempDir dir;
  const fs::path bad = dir / "broken.jpg";
  copy_prefix(sample1(), bad, 2000);  // a JPEG cut short: the header, no picture
  const fs::path data_dir = dir / "data";
  {
    data::SqliteStore store(store_at(data::database_path(data_dir)));
    FaceGallery(store).enroll("Bob", {std::vector<float>(128, 0.1f)}, "test");
  }
  // A good photo of one person (a crop of the group photo), then the broken one.
  const fs::path good = dir / "anna.png";
  cv::imwrite(good.string(), read_photo(sample1())(cv::Rect(250, 250, 550, 550)));
  const auto before = test_support::snapshot(data_dir);
  const fs::path marvin = fs::path(std::getenv("MARVIN_BUILD_DIR")) / "core/app/marvin";
  test_support::ChildProcess p({marvin.string(), "people", "enroll", "Anna", good.string(),
                                bad.string(), "--data-dir", data_dir.string()});
  CHECK(test_support::exit_code(p.finish()) == 1);
  CHECK(contains(p.errors(), "photo " + bad.string()));
  CHECK(contains(p.errors(), "not an image OpenCV can decode"));
  CHECK(test_support::snapshot(data_dir) == before);
}

TEST_CASE("a corrupt photo is an error naming the file") {
  TempDir dir;
  std::ofstream(dir / "noise.png") << "not a picture at all";
  CHECK(contains(error_of([&] { read_photo(dir / "noise.png"); }), "noise.png"));
  FolderCamera camera(dir.path());
  Frame frame;
  const std::string e = error_of([&] { camera.read(frame); });
  CHECK(contains(e, "noise.png"));
  CHECK(contains(e, "not an image"));
}

TEST_CASE("broken, wrong and missing models are errors naming the file and scripts/setup") {
  TempDir dir;
  const fs::path model = find_model(kFaceRecognitionModel);
  copy_prefix(model, dir / "cut.mvt", 100'000);
  const std::string cut = error_of([&] { FaceEmbedder e(dir / "cut.mvt"); });
  CHECK(contains(cut, "cut.mvt"));
  CHECK(contains(cut, "truncated at byte"));
  CHECK(contains(cut, "scripts/setup"));

  fs::copy_file(sample1(), dir / "photo.mvt");
  CHECK(contains(error_of([&] { FaceEmbedder e(dir / "photo.mvt"); }),
                 "not a Marvin tensor file"));

  TensorMap wrong{{"conv32_down/weights", {{32, 3, 5, 5}, std::vector<float>(32 * 3 * 25)}}};
  write_tensor_file(dir / "wrong.mvt", wrong);
  CHECK(contains(error_of([&] { FaceEmbedder e(dir / "wrong.mvt"); }),
                 "conv32_down/weights has shape 32x3x5x5, expected 32x3x7x7"));

  const std::string missing = error_of([] { find_model("no_such_model.mvt"); });
  CHECK(contains(missing, "no_such_model.mvt"));
  CHECK(contains(missing, "run scripts/setup"));
  CHECK(contains(error_of([&] { FaceEmbedder e(dir / "gone.mvt"); }), "scripts/setup"));

  copy_prefix(find_model(kBlazeFaceBackModel), dir / "cut.onnx", 5000);
  const std::string onnx = error_of([&] {
    BlazeFaceDetector d(BlazeFaceDetector::Range::kBack256, 0.6f, dir / "cut.onnx");
  });
  CHECK(contains(onnx, "cut.onnx"));
  CHECK(contains(onnx, "scripts/setup"));
}

TEST_CASE("a camera that vanishes is an error naming it") {
  CHECK(contains(error_of([] { VideoCaptureCamera c("/dev/marvin-no-such-camera"); }),
                 "camera /dev/marvin-no-such-camera"));
  TempDir dir;
  fs::copy_file(sample1(), dir / "a.jpg");
  fs::copy_file(sample1(), dir / "b.jpg");
  FolderCamera camera(dir.path());
  Frame frame;
  REQUIRE(camera.read(frame));
  CHECK(frame.image.cols == 1920);
  fs::remove(dir / "b.jpg");
  const std::string e = error_of([&] { camera.read(frame); });
  CHECK(contains(e, "b.jpg"));
  CHECK(contains(e, "vanished"));
  CHECK(contains(error_of([&] { FolderCamera c(dir / "nowhere"); }), "not a directory"));
}

TEST_CASE("the vision graph keeps running while its camera is missing, and reports it") {
  register_vision_nodes();
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> warnings;
  auto previous = set_log_sink([&](LogLevel level, std::string_view, std::string_view msg) {
    if (level != LogLevel::kWarning) return;
    std::lock_guard lock(m);
    warnings.emplace_back(msg);
    cv.notify_all();
  });
  graph::GraphConfig config;
  config.add_node("camera", "CameraSource",
                  {{"camera", "device:/dev/marvin-no-such-camera"}, {"retry_ms", 20}});
  config.add_node("faces", "FaceDetectorNode");
  config.add_node("log", "FaceLogger");
  config.connect("camera.frames", "faces.in");
  config.connect("faces.out", "log.in");
  graph::Graph g(config);
  g.start();
  {
    std::unique_lock lock(m);
    // Two reports: the failed open at start and at least one retry.
    CHECK(cv.wait_for(lock, std::chrono::seconds(60), [&] { return warnings.size() >= 2; }));
    CHECK(contains(warnings.front(), "/dev/marvin-no-such-camera"));
    CHECK(contains(warnings.front(), "retrying"));
  }
  g.stop();
  CHECK_NOTHROW(g.wait());
  set_log_sink(previous);
}

TEST_CASE("a folder of real photos runs through the whole face graph") {
  register_vision_nodes();
  TempDir dir;
  fs::copy_file(sample1(), dir / "a.jpg");
  {
    data::SqliteStore store(store_at(dir / "marvin.db"));
    FacePipeline pipeline("blazeface");
    const auto faces = pipeline.faces(read_photo(sample1()));
    FaceGallery(store).enroll("Anna", {face_at(faces, kSample1Faces[0]).embedding}, "test");
  }
  graph::GraphConfig config;
  config.add_node("camera", "CameraSource", {{"camera", "folder:" + dir.path().string()}});
  config.add_node("faces", "FaceDetectorNode");
  config.add_node("embed", "FaceEmbedderNode");
  config.add_node("who", "FaceIdentifierNode", {{"database", (dir / "marvin.db").string()}});
  config.add_node("log", "FaceLogger");
  config.connect("camera.frames", "faces.in");
  config.connect("faces.out", "embed.in");
  config.connect("embed.out", "who.in");
  config.connect("who.out", "log.in");
  graph::Graph g(config);
  std::vector<FaceList> seen;
  g.observe("who.out", [&](const graph::Packet& p) { seen.push_back(p.get<FaceList>()); });
  g.start();
  g.wait();
  REQUIRE(seen.size() == 1);
  REQUIRE(seen[0].faces.size() == 3);
  CHECK(face_at(seen[0].faces, kSample1Faces[0]).name == "Anna");
  CHECK(face_at(seen[0].faces, kSample1Faces[1]).name.empty());
}

TEST_CASE("teach by showing: a taught region is found again turned and smaller, after a reopen") {
  TempDir dir;
  const cv::Mat image = read_photo(sample1());
  const cv::Rect region(330, 320, 320, 320);  // the first woman's head and hair
  {
    data::SqliteStore store(store_at(dir / "marvin.db"));
    ObjectMemory(store).teach("my photo", image, region);
  }
  data::SqliteStore store(store_at(dir / "marvin.db"));
  ObjectMemory memory(store);
  CHECK(memory.names() == std::vector<std::string>{"my photo"});
  // The whole picture turned by 20 degrees about its centre and scaled to 70%.
  const cv::Point2f centre(static_cast<float>(image.cols) / 2, static_cast<float>(image.rows) / 2);
  const cv::Mat m = cv::getRotationMatrix2D(centre, 20, 0.7);
  cv::Mat turned;
  cv::warpAffine(image, turned, m, image.size());
  const auto seen = memory.find("my photo", turned);
  REQUIRE(seen.has_value());
  CHECK(seen->inliers >= ObjectMemory::kMinInliers);
  std::vector<cv::Point2f> expected;
  cv::transform(std::vector<cv::Point2f>{{490, 480}}, expected, m);
  const cv::Point2f found(seen->box.x + seen->box.width / 2, seen->box.y + seen->box.height / 2);
  CHECK(cv::norm(found - expected[0]) < 30);
  // Not in a photo of other people.
  const cv::Mat other = read_photo(source_dir() / ".cache/vision/photos/sample3.jpg");
  CHECK_FALSE(memory.find("my photo", other).has_value());
  CHECK(memory.find_all(turned).size() == 1);
  CHECK(memory.forget("my photo"));
  CHECK(memory.names().empty());
  CHECK(contains(error_of([&] { (void)memory.find("my photo", turned); }),
                 "no object called my photo"));
}

TEST_CASE("a plain thing cannot be taught, and nothing is stored") {
  TempDir dir;
  data::SqliteStore store(store_at(dir / "marvin.db"));
  ObjectMemory memory(store);
  const cv::Mat plain(480, 640, CV_8UC3, cv::Scalar(90, 90, 90));
  CHECK(contains(error_of([&] { memory.teach("wall", plain); }), "wall looks too plain"));
  CHECK(contains(error_of([&] { memory.teach("x", plain, cv::Rect(600, 400, 100, 100)); }),
                 "outside the picture"));
  CHECK(memory.names().empty());
  CHECK_FALSE(store.storage_get("marvin.vision.objects", "object:wall").has_value());
}

TEST_CASE("marvin people enroll, list and forget through the real program and SQLite file") {
  TempDir dir;
  const fs::path good = dir / "anna.png";
  cv::imwrite(good.string(), read_photo(sample1())(cv::Rect(250, 250, 550, 550)));
  const std::string marvin = (fs::path(std::getenv("MARVIN_BUILD_DIR")) / "core/app/marvin").string();
  const std::string data_dir = (dir / "data").string();
  auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), marvin);
    args.push_back("--data-dir");
    args.push_back(data_dir);
    test_support::ChildProcess p(args);
    const int code = test_support::exit_code(p.finish());
    return std::pair{code, p.output() + p.errors()};
  };
  const auto enrolled = run({"people", "enroll", "Anna", good.string()});
  CHECK(enrolled.first == 0);
  CHECK(contains(enrolled.second, "enrolled Anna from 1 photo"));
  const auto listed = run({"people", "list"});
  CHECK(contains(listed.second, "Anna  1 face embedding"));
  CHECK(contains(listed.second, "last added by cli at "));
  const auto renamed = run({"people", "rename", "Anna", "Anna Schmidt"});
  CHECK(renamed.first == 0);
  CHECK(contains(renamed.second, "Anna is now called Anna Schmidt"));
  CHECK(contains(run({"people", "list"}).second, "Anna Schmidt  1 face embedding"));
  CHECK(run({"people", "rename", "Anna Schmidt", "Anna"}).first == 0);
  CHECK(run({"people", "forget", "Anna"}).first == 0);
  CHECK_FALSE(contains(run({"people", "list"}).second, "Anna"));
  const auto again = run({"people", "forget", "Anna"});
  CHECK(again.first == 1);
  CHECK(contains(again.second, "nobody called Anna is enrolled"));
}
