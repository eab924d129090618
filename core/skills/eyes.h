// Eyes: what the host's camera lends to skills (Robot API 1.2: vision_look, ...). The real
// one is core/vision's VisionEyes (camera + face pipeline + the people gallery); the
// MockRobot serves a scripted view. Kept free of OpenCV so core/skills does not need it.
#pragma once

#include <stdexcept>
#include <string>

namespace marvin::skills {

// The camera is missing, failed or vanished: the message names it. Becomes
// MARVIN_ERR_UNAVAILABLE.
class EyesUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// No face (MARVIN_ERR_NOT_FOUND) or several faces (MARVIN_ERR_INVALID) where one was needed.
class NoSingleFace : public std::runtime_error {
 public:
  NoSingleFace(const std::string& message, int faces)
      : std::runtime_error(message), faces_(faces) {}
  int faces() const { return faces_; }

 private:
  int faces_;
};

class Eyes {
 public:
  virtual ~Eyes() = default;
  // The JSON documented at vision_look in marvin/robot.h.
  virtual std::string look_json() = 0;
  // Saves a photo for `skill_id` and returns its path.
  virtual std::string capture_photo(const std::string& skill_id) = 0;
  // Enrols the one face in view from up to `frames` frames; returns the frames used.
  // `who` is recorded with the enrolment ("skill:<id>").
  virtual int enroll_face(const std::string& name, int frames, const std::string& who) = 0;
  // False if nobody of that name is enrolled.
  virtual bool forget_face(const std::string& name, const std::string& who) = 0;
  // "These are my keys": learns the look of what is held up in the middle of the view.
  // Throws std::invalid_argument (MARVIN_ERR_INVALID) when it is too plain to recognise.
  virtual void teach_object(const std::string& name) = 0;
  // {"name", "found": bool, "box": [x, y, w, h]}; nullopt-like "" when `name` was never
  // taught (MARVIN_ERR_NOT_FOUND).
  virtual std::string find_object_json(const std::string& name) = 0;
};

}  // namespace marvin::skills
