// Robot API 1.2 (seeing) through the MockRobot: a scripted camera view, enrolment and
// forgetting by face, permissions, a camera that fails; bad calls change nothing.
#include <doctest/doctest.h>

#include <marvin/skill.hpp>
#include <marvin/testing/mock_robot.hpp>

namespace {

const char* kOneStranger = R"({"width":640,"height":480,
  "faces":[{"name":"","box":[200,120,140,140],"distance":0.9}],
  "objects":[{"label":"cup","box":[400,300,60,80],"score":0.8}]})";

marvin::Error error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const marvin::Error& e) {
    return e;
  }
  return marvin::Error(MARVIN_OK, "(no error)");
}

}  // namespace

TEST_CASE("a robot without a camera says so") {
  marvin::testing::MockRobot mock("faces", {"camera", "faces"});
  marvin::Robot robot(mock.api(), mock.host());
  const auto e = error_of([&] { robot.vision_look(); });
  CHECK(e.status() == MARVIN_ERR_UNAVAILABLE);
  CHECK(std::string(e.what()).find("camera") != std::string::npos);
}

TEST_CASE("the scripted camera: look, enrol the one face, look again, forget") {
  marvin::testing::MockRobot mock("faces", {"camera", "faces"});
  mock.set_camera_view(kOneStranger);
  marvin::Robot robot(mock.api(), mock.host());
  nlohmann::json seen = robot.vision_look();
  REQUIRE(seen["faces"].size() == 1);
  CHECK(seen["faces"][0]["name"] == "");
  CHECK(seen["objects"][0]["label"] == "cup");

  const nlohmann::json result = robot.vision_enroll_face("Anna", 3);
  CHECK(result["name"] == "Anna");
  CHECK(result["frames_used"] == 3);
  CHECK(robot.vision_look()["faces"][0]["name"] == "Anna");
  CHECK(mock.enrolled_faces() == std::vector<std::string>{"Anna"});

  CHECK(robot.vision_capture_photo() == "/mock/faces/photo-1.jpg");
  robot.vision_forget_face("Anna");
  CHECK(mock.enrolled_faces().empty());
  CHECK(robot.vision_look()["faces"][0]["name"] == "");
  CHECK(error_of([&] { robot.vision_forget_face("Anna"); }).status() == MARVIN_ERR_NOT_FOUND);
  CHECK(mock.actions() == std::vector<std::string>{"enroll_face Anna frames=3", "capture_photo",
                                                   "forget_face Anna"});
}

TEST_CASE("enrolment needs the faces permission, one face and sane arguments; nothing changes otherwise") {
  marvin::testing::MockRobot mock("faces", {"camera"});
  mock.set_camera_view(
      R"({"faces":[{"name":"","box":[0,0,10,10]},{"name":"","box":[50,0,10,10]}]})");
  marvin::Robot robot(mock.api(), mock.host());
  const auto denied = error_of([&] { robot.vision_enroll_face("Anna", 3); });
  CHECK(denied.status() == MARVIN_ERR_PERMISSION);
  CHECK(std::string(denied.what()) == "permission 'faces' is not granted to skill 'faces'");

  mock.set_permissions({"camera", "faces"});
  const auto two = error_of([&] { robot.vision_enroll_face("Anna", 3); });
  CHECK(two.status() == MARVIN_ERR_INVALID);
  CHECK(std::string(two.what()).find("2 faces") != std::string::npos);
  CHECK(error_of([&] { robot.vision_enroll_face("Anna", 0); }).status() == MARVIN_ERR_INVALID);
  CHECK(error_of([&] { robot.vision_enroll_face("", 3); }).status() == MARVIN_ERR_INVALID);
  mock.set_camera_view(R"({"faces":[]})");
  CHECK(error_of([&] { robot.vision_enroll_face("Anna", 3); }).status() == MARVIN_ERR_NOT_FOUND);
  CHECK(mock.enrolled_faces().empty());
  CHECK(mock.actions().empty());
}

TEST_CASE("a camera that fails is reported and nothing is enrolled") {
  marvin::testing::MockRobot mock("faces", {"camera", "faces"});
  mock.set_camera_view(kOneStranger);
  mock.set_camera_failure("camera /dev/video0: reading a frame failed (device unplugged?)");
  marvin::Robot robot(mock.api(), mock.host());
  const auto e = error_of([&] { robot.vision_enroll_face("Anna", 3); });
  CHECK(e.status() == MARVIN_ERR_UNAVAILABLE);
  CHECK(std::string(e.what()) == "camera /dev/video0: reading a frame failed (device unplugged?)");
  CHECK(error_of([&] { robot.vision_look(); }).status() == MARVIN_ERR_UNAVAILABLE);
  CHECK(mock.enrolled_faces().empty());
}
