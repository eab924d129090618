#include "vision/face_pipeline.h"

#include <algorithm>
#include <stdexcept>

namespace marvin::vision {

FacePipeline::FacePipeline(const std::string& detector)
    : detector_(make_face_detector(detector)) {}

std::vector<Face> FacePipeline::faces(const cv::Mat& image_bgr) {
  std::vector<Face> found = detector_->detect(image_bgr);
  for (Face& f : found) f.embedding = embedder_.embed_chip(face_chip(image_bgr, f));
  return found;
}

std::optional<Face> FacePipeline::main_face(const cv::Mat& image_bgr, bool whole_if_none) {
  std::vector<Face> found = detector_->detect(image_bgr);
  Face face;
  if (!found.empty()) {
    face = *std::max_element(found.begin(), found.end(), [](const Face& a, const Face& b) {
      return a.box.area() < b.box.area();
    });
  } else if (whole_if_none) {
    face.box = cv::Rect2f(0, 0, static_cast<float>(image_bgr.cols),
                          static_cast<float>(image_bgr.rows));
    face.score = 0;
  } else {
    return std::nullopt;
  }
  face.embedding = embedder_.embed_chip(face_chip(image_bgr, face));
  return face;
}

std::vector<float> lone_face_embedding(FacePipeline& pipeline, const cv::Mat& image_bgr,
                                       const std::string& photo, const std::string& who) {
  std::vector<Face> found = pipeline.faces(image_bgr);
  if (found.empty()) {
    throw std::invalid_argument("photo " + photo + ": no face found (detector " +
                                pipeline.detector().name() + ")");
  }
  if (found.size() > 1) {
    throw std::invalid_argument("photo " + photo + ": " + std::to_string(found.size()) +
                                " faces; give photos of " + who + " alone");
  }
  return std::move(found.front().embedding);
}

}  // namespace marvin::vision
