#include "vision/vision_eyes.h"

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>

#include <opencv2/imgcodecs.hpp>

#include "common/log.h"
#include "vision/cameras.h"
#include "vision/face_gallery.h"
#include "vision/model_files.h"
#include "vision/object_memory.h"
#include "vision/object_names.h"

namespace marvin::vision {

VisionEyes::VisionEyes(std::string camera, data::SqliteStore* store,
                       std::filesystem::path photos_dir, std::string detector)
    : spec_(std::move(camera)),
      store_(store),
      photos_dir_(std::move(photos_dir)),
      detector_(std::move(detector)) {}

VisionEyes::VisionEyes(std::function<std::unique_ptr<Camera>()> open, std::string name,
                       data::SqliteStore* store, std::filesystem::path photos_dir,
                       std::string detector)
    : spec_(std::move(name)),
      open_(std::move(open)),
      store_(store),
      photos_dir_(std::move(photos_dir)),
      detector_(std::move(detector)) {}

Frame VisionEyes::grab() {
  try {
    if (!camera_) {
      if (open_) {
        camera_ = open_();
      } else if (spec_.rfind("folder:", 0) == 0) {
        camera_ = std::make_unique<FolderCamera>(spec_.substr(7), /*loop=*/true);
      } else {
        camera_ = open_camera(spec_);
      }
    }
    Frame frame;
    if (!camera_->read(frame)) {
      camera_.reset();
      throw CameraError("camera " + spec_ + ": no more frames");
    }
    return frame;
  } catch (const CameraError& e) {
    camera_.reset();  // opened again at the next call
    throw skills::EyesUnavailable(e.what());
  }
}

FacePipeline& VisionEyes::pipeline() {
  if (!pipeline_) {
    try {
      pipeline_ = std::make_unique<FacePipeline>(detector_);
    } catch (const ModelError& e) {
      throw skills::EyesUnavailable(e.what());
    }
  }
  return *pipeline_;
}

ObjectDetector* VisionEyes::objects() {
  if (!objects_tried_) {
    objects_tried_ = true;
    try {
      objects_ = std::make_unique<ObjectDetector>();
    } catch (const ModelError& e) {
      marvin::log(LogLevel::kWarning, "vision", std::string("no object detection: ") + e.what());
    }
  }
  return objects_.get();
}

std::string VisionEyes::look_json() {
  std::lock_guard lock(mutex_);
  const Frame frame = grab();
  nlohmann::json faces = nlohmann::json::array();
  std::unique_ptr<FaceGallery> gallery;
  if (store_) gallery = std::make_unique<FaceGallery>(*store_);
  for (const Face& f : pipeline().faces(frame.image)) {
    FaceMatch m;
    if (gallery) m = gallery->identify(f.embedding);
    faces.push_back({{"name", m.known ? m.name : ""},
                     {"box", {f.box.x, f.box.y, f.box.width, f.box.height}},
                     {"distance", m.distance}});
  }
  nlohmann::json objects = nlohmann::json::array();
  if (ObjectDetector* detector = this->objects()) {
    for (const DetectedObject& o : detector->detect(frame.image)) {
      objects.push_back({{"label", o.label},
                         {"class", o.coco},
                         {"box", {o.box.x, o.box.y, o.box.width, o.box.height}},
                         {"score", o.score}});
    }
  }
  if (store_) {
    for (const auto& o : ObjectMemory(*store_).find_all(frame.image)) {
      objects.push_back({{"label", o.name},
                         {"box", {o.box.x, o.box.y, o.box.width, o.box.height}},
                         {"score", 1.0}});
    }
  }
  return nlohmann::json{{"width", frame.image.cols},
                        {"height", frame.image.rows},
                        {"faces", faces},
                        {"objects", objects}}
      .dump();
}

std::string VisionEyes::capture_photo(const std::string& skill_id) {
  std::lock_guard lock(mutex_);
  const Frame frame = grab();
  const auto dir = photos_dir_ / skill_id;
  std::filesystem::create_directories(dir);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  const auto path = dir / ("photo-" + std::to_string(ms) + ".jpg");
  if (!cv::imwrite(path.string(), frame.image)) {
    throw std::runtime_error("cannot write the photo " + path.string());
  }
  return path.string();
}

int VisionEyes::enroll_face(const std::string& name, int frames, const std::string& who) {
  std::lock_guard lock(mutex_);
  if (!store_) {
    throw skills::EyesUnavailable("enrolling a face needs the SQLite store (not --in-memory)");
  }
  // Every frame must show exactly one face; nothing is stored unless all of them do.
  std::vector<std::vector<float>> embeddings;
  for (int i = 0; i < frames; ++i) {
    const Frame frame = grab();
    const auto faces = pipeline().faces(frame.image);
    if (faces.size() != 1) {
      const int n = static_cast<int>(faces.size());
      throw skills::NoSingleFace(n == 0 ? "no face in view" :
                                 std::to_string(n) + " faces in view; one at a time please",
                                 n);
    }
    embeddings.push_back(faces.front().embedding);
  }
  FaceGallery(*store_).enroll(name, embeddings, who);
  return frames;
}

bool VisionEyes::forget_face(const std::string& name, const std::string& who) {
  std::lock_guard lock(mutex_);
  if (!store_) return false;
  return FaceGallery(*store_).forget(name, who);
}

void VisionEyes::teach_object(const std::string& name) {
  std::lock_guard lock(mutex_);
  if (!store_) {
    throw skills::EyesUnavailable("learning an object needs the SQLite store (not --in-memory)");
  }
  const Frame frame = grab();
  ObjectMemory(*store_).teach(name, frame.image);
}

std::string VisionEyes::find_object_json(const std::string& name) {
  std::lock_guard lock(mutex_);
  std::vector<std::string> taught;
  if (store_) taught = ObjectMemory(*store_).names();
  if (std::find(taught.begin(), taught.end(), name) == taught.end()) {
    // Not taught, but a COCO class ("phone", "mug", "bike"): the detector looks for it. The
    // answer names it as Marvin says it ("phone"), which is also how looks and sightings
    // name it (finding skill, issue 22).
    const std::optional<std::string> coco = coco_class_for(name);
    ObjectDetector* detector = coco ? objects() : nullptr;
    if (!detector) return "";
    const Frame frame = grab();
    nlohmann::json out = {{"name", spoken_name(*coco)}, {"found", false}, {"class", *coco}};
    for (const DetectedObject& o : detector->detect(frame.image)) {
      if (o.coco != *coco) continue;
      out["found"] = true;
      out["box"] = {o.box.x, o.box.y, o.box.width, o.box.height};
      break;
    }
    return out.dump();
  }
  ObjectMemory memory(*store_);
  const Frame frame = grab();
  nlohmann::json out = {{"name", name}, {"found", false}};
  if (const auto seen = memory.find(name, frame.image)) {
    out["found"] = true;
    out["box"] = {seen->box.x, seen->box.y, seen->box.width, seen->box.height};
  }
  return out.dump();
}

}  // namespace marvin::vision
