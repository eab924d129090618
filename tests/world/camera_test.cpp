// The simulated camera: an object's photo lands where the geometry says, scaled by
// distance, and a wall in between hides it.
#include "sim/camera.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "sim/sim_runner.h"
#include "support/files.h"

using marvin::sim::CameraView;
using marvin::sim::SimCamera;

namespace {

// A 10 m x 6 m room with a pure red card 1 m tall standing at (5, 3); an inner wall
// at x = 7 from y = 0 to 6 with a gap... no gap: the far side is hidden.
marvin::sim::World red_card_world(const std::filesystem::path& dir) {
  cv::Mat red(200, 100, CV_8UC3, cv::Scalar(0, 0, 255));
  cv::imwrite((dir / "red.png").string(), red);
  return marvin::sim::parse_world(R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[10,0],[10,6],[0,6]], "floor_colour": "#404040"}],
    "walls": [{"from": [7, 0.5], "to": [7, 5.5]}],
    "objects": [{"name": "card", "at": [5, 3], "room": "hall", "size_m": 1.0, "photo": "red.png"},
                {"name": "hidden", "at": [8.5, 3], "room": "hall", "size_m": 1.0, "photo": "red.png"}],
    "robot": {"start": [3, 3], "heading_deg": 0, "camera_height_m": 0.5}})",
                                  dir / "world.json");
}

bool red(const cv::Mat& img, int x, int y) {
  cv::Vec3b p = img.at<cv::Vec3b>(y, x);
  return p[2] > 200 && p[1] < 40 && p[0] < 40;
}

int red_pixels(const cv::Mat& img) {
  int n = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) n += red(img, x, y);
  return n;
}

}  // namespace

TEST_CASE("the card is where the pinhole geometry puts it, at its scale") {
  marvin::test_support::TempDir dir;
  marvin::sim::World world = red_card_world(dir.path());
  CameraView view{world.robot.start, 0, 0};
  SimCamera camera(world, [&] { return view; });
  marvin::vision::Frame frame;
  REQUIRE(camera.read(frame));
  REQUIRE(frame.image.cols == 640);
  REQUIRE(frame.image.rows == 480);
  // focal = 320 / tan 30 = 554.3 px; the card 2 m ahead: 1 m tall = 277 px, 0.5 m wide =
  // 139 px, centred; its foot on the floor 0.5 m below the camera: 240 + 554.3 * 0.5 / 2.
  const double f = 320 / std::tan(30 * marvin::navigation::kPi / 180);
  const int foot = static_cast<int>(240 + f * 0.5 / 2), top = static_cast<int>(foot - f / 2);
  const int half = static_cast<int>(f * 0.25 / 2);
  CHECK(red(frame.image, 320, (foot + top) / 2));
  CHECK(red(frame.image, 320 - half + 3, foot - 3));
  CHECK_FALSE(red(frame.image, 320 - half - 4, (foot + top) / 2));
  CHECK_FALSE(red(frame.image, 320, foot + 4));
  CHECK_FALSE(red(frame.image, 320, top - 4));
  CHECK(red_pixels(frame.image) == doctest::Approx(2 * half * (foot - top)).epsilon(0.05));
  // Turned 90 degrees left: the card is out of view.
  view.pose.heading = marvin::navigation::kPi / 2;
  camera.read(frame);
  CHECK(red_pixels(frame.image) == 0);
  CHECK(frame.index == 1);
}

TEST_CASE("a wall in between hides the photo; tilting the head moves it down") {
  marvin::test_support::TempDir dir;
  marvin::sim::World world = red_card_world(dir.path());
  // Past the first card (turned away from it is not needed: stand beside it at x = 5.5).
  CameraView view{{5.5, 3, 0}, 0, 0};
  SimCamera camera(world, [&] { return view; });
  marvin::vision::Frame frame;
  camera.read(frame);
  CHECK(red_pixels(frame.image) == 0);  // "hidden" stands behind the wall at x = 7
  REQUIRE(camera.project(world.objects[1], view).has_value());
  // Back at the start: tilt up 20 degrees, the card moves down by f tan 20.
  view = {world.robot.start, 0, 0};
  auto level = camera.project(world.objects[0], view);
  view.head_deg = 20;
  auto up = camera.project(world.objects[0], view);
  REQUIRE(level);
  REQUIRE(up);
  CHECK(up->y - level->y ==
        doctest::Approx(554.3 * std::tan(20 * marvin::navigation::kPi / 180)).epsilon(0.02));
}

TEST_CASE("a missing photo is a CameraError naming the file") {
  marvin::test_support::TempDir dir;
  marvin::sim::World world = red_card_world(dir.path());
  std::filesystem::remove(dir.path() / "red.png");
  CHECK_THROWS_WITH_AS(SimCamera(world, [] { return CameraView{}; }),
                       doctest::Contains("red.png of \"card\""), marvin::vision::CameraError);
}

TEST_CASE("the camera of the simulated robot follows its pose and head") {
  marvin::sim::SimRunner runner(marvin::sim::load_world(marvin::sim::default_world_file()), {},
                                1.0);
  SimCamera camera(runner.world(), [&] { return runner.camera_view(); });
  marvin::vision::Frame first, second;
  REQUIRE(camera.read(first));
  runner.move(marvin::devices::Direction::kLeft, 120, std::chrono::milliseconds(800));
  runner.advance(std::chrono::milliseconds(1000));
  REQUIRE(camera.read(second));
  CHECK(second.index == 1);
  CHECK(second.time_us == 1'000'000);
  CHECK(cv::norm(first.image, second.image, cv::NORM_L1) > 0);  // it turned: another view
  CHECK(camera.describe().find("simulated camera") == 0);
}
