// The simulated camera with a real face: face-api's demo photo (fetched by
// scripts/setup, as tests/vision uses it) on Anna's card, run through vision's
// real BlazeFace detector.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "sim/camera.h"
#include "sim/world.h"
#include "vision/face_detector.h"

namespace fs = std::filesystem;

namespace {

fs::path setup_photos() {
  const char *s = std::getenv("MARVIN_SOURCE_DIR");
  REQUIRE_MESSAGE(s != nullptr, "MARVIN_SOURCE_DIR is set by ctest");
  const fs::path p = fs::path(s) / ".cache/vision/photos";
  REQUIRE_MESSAGE(fs::exists(p / "sample1.jpg"), (p / "sample1.jpg").string()
                                                     << " is missing: run scripts/setup");
  return p;
}

// A 6 m x 4 m room; Anna 1.5 m in front of the robot, her card the crop of
// sample1 around the left person's face (face centre at (517, 506) of the
// photo: (267, 256) of the crop).
marvin::sim::World anna_world(const fs::path &photos) {
  return marvin::sim::parse_world(R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "living room", "outline": [[0,0],[6,0],[6,4],[0,4]]}],
    "people": [{"name": "Anna", "at": [4, 2], "room": "living room", "size_m": 0.45,
                "elevation_m": 0.5, "photo": "sample1.jpg", "crop": [250, 250, 550, 550]}],
    "robot": {"start": [2.5, 2], "heading_deg": 0}})",
                                  photos / "world.json");
}

}  // namespace

TEST_CASE(
    "facing Anna at 1.5 m, BlazeFace finds her face where the geometry "
    "puts it") {
  const marvin::sim::World world = anna_world(setup_photos());
  const marvin::sim::CameraView view{world.robot.start, 0, 0};
  marvin::sim::SimCamera camera(world, [&] { return view; });
  marvin::vision::Frame frame;
  REQUIRE(camera.read(frame));
  const auto card = camera.project(world.people.at(0), view);
  REQUIRE(card.has_value());
  const cv::Point2f expected(static_cast<float>(card->x + card->width * 267.0 / 550),
                             static_cast<float>(card->y + card->height * 256.0 / 550));
  marvin::vision::BlazeFaceDetector detector;
  const auto faces = detector.detect(frame.image);
  REQUIRE(faces.size() == 1);
  INFO("face box " << faces[0].box.x << "," << faces[0].box.y << " " << faces[0].box.width << "x"
                   << faces[0].box.height << "; expected centre " << expected.x << ","
                   << expected.y);
  CHECK(faces[0].box.contains(expected));
  // About the size the photo's face has at this scale (the face is ~1/4 of the
  // crop).
  CHECK(faces[0].box.width > card->width / 8.0);
  CHECK(faces[0].box.width < card->width / 1.5);

  // Turned away from her: no face.
  const marvin::sim::CameraView away{{2.5, 2, marvin::navigation::kPi}, 0, 0};
  marvin::sim::SimCamera turned(world, [&] { return away; });
  REQUIRE(turned.read(frame));
  CHECK(detector.detect(frame.image).empty());
}

TEST_CASE("a crop outside the photo is an error naming the person and the photo") {
  const fs::path photos = setup_photos();
  const marvin::sim::World world = marvin::sim::parse_world(
      R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[6,0],[6,4],[0,4]]}],
    "people": [{"name": "Anna", "at": [4, 2], "room": "hall", "photo": "sample1.jpg",
                "crop": [1800, 0, 300, 300]}],
    "robot": {"start": [2.5, 2]}})",
      photos / "world.json");
  std::string error;
  try {
    marvin::sim::SimCamera camera(world, [] { return marvin::sim::CameraView{}; });
  } catch (const marvin::vision::CameraError &e) {
    error = e.what();
  }
  CHECK(error.find("'crop' of \"Anna\"") != std::string::npos);
  CHECK(error.find("sample1.jpg (1920x1280)") != std::string::npos);
}

TEST_CASE("a missing setup photo is an error naming it and scripts/setup") {
  const marvin::sim::World world = marvin::sim::parse_world(
      R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[6,0],[6,4],[0,4]]}],
    "people": [{"name": "Anna", "at": [4, 2], "room": "hall",
                "photo": ".cache/vision/photos/no-such-sample.jpg"}],
    "robot": {"start": [2.5, 2]}})",
      "/nonexistent/world.json");
  std::string error;
  try {
    marvin::sim::SimCamera camera(world, [] { return marvin::sim::CameraView{}; });
  } catch (const marvin::vision::CameraError &e) {
    error = e.what();
  }
  CHECK(error.find("no-such-sample.jpg of \"Anna\"") != std::string::npos);
  CHECK(error.find("scripts/setup fetches it") != std::string::npos);
}

TEST_CASE("a malformed crop is a world error naming the person and the field") {
  std::string error;
  try {
    marvin::sim::parse_world(R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[6,0],[6,4],[0,4]]}],
    "people": [{"name": "Anna", "at": [4, 2], "room": "hall", "photo": "a.jpg",
                "crop": [0, 0, 0, 10]}],
    "robot": {"start": [2.5, 2]}})",
                             "w.json");
  } catch (const marvin::sim::WorldError &e) {
    error = e.what();
  }
  CHECK(error.find("Anna") != std::string::npos);
  CHECK(error.find("'crop' must be [x, y, width, height]") != std::string::npos);
}
