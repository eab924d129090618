#include "vision/face_pipeline.h"

#include <algorithm>

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

}  // namespace marvin::vision
