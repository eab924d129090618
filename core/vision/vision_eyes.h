// VisionEyes: the host's camera for the Robot API (skills::Eyes, API 1.2): a Camera, the
// face pipeline, the COCO object detector and the people gallery in the owner's SQLite
// store. The camera and the
// models are opened at the first call, and the camera again after it failed, so a robot
// whose camera is unplugged keeps running and answers MARVIN_ERR_UNAVAILABLE with the
// camera's own message until it is back. Thread-safe (one call at a time).
#ifndef MARVIN_VISION_VISION_EYES_H_
#define MARVIN_VISION_VISION_EYES_H_

#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "data/sqlite_store.h"
#include "skills/eyes.h"
#include "vision/camera.h"
#include "vision/face_pipeline.h"
#include "vision/object_detector.h"

namespace marvin::vision {

class VisionEyes final : public skills::Eyes {
 public:
  // `camera`: see open_camera() (a folder camera loops). `store`: null with in-memory data
  // (then faces are never named and enrolment is unavailable). Photos go to `photos_dir`.
  VisionEyes(std::string camera, data::SqliteStore* store, std::filesystem::path photos_dir,
             std::string detector = "blazeface");
  // Looks through the camera `open` makes (called at the first look, and again after a
  // camera error); `name` names it in errors. `marvin run --sim` passes the simulated
  // home's camera this way.
  VisionEyes(std::function<std::unique_ptr<Camera>()> open, std::string name,
             data::SqliteStore* store, std::filesystem::path photos_dir,
             std::string detector = "blazeface");

  std::string look_json() override;
  std::string capture_photo(const std::string& skill_id) override;
  int enroll_face(const std::string& name, int frames, const std::string& who) override;
  bool forget_face(const std::string& name, const std::string& who) override;
  void teach_object(const std::string& name) override;
  std::string find_object_json(const std::string& name) override;

 private:
  Frame grab();  // throws EyesUnavailable
  FacePipeline& pipeline();
  // The COCO detector, loaded at the first look; null (and logged once) when its model is
  // missing: then looks report faces and taught objects only.
  ObjectDetector* objects();

  std::mutex mutex_;
  std::string spec_;
  std::function<std::unique_ptr<Camera>()> open_;  // null: open spec_
  data::SqliteStore* store_;
  std::filesystem::path photos_dir_;
  std::string detector_;
  std::unique_ptr<Camera> camera_;
  std::unique_ptr<FacePipeline> pipeline_;
  std::unique_ptr<ObjectDetector> objects_;
  bool objects_tried_ = false;
};

}  // namespace marvin::vision

#endif  // MARVIN_VISION_VISION_EYES_H_
