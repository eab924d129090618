// FacePipeline: detector + embedder together, what enrolment, the evaluation tool, the graph
// and the robot API use to go from a picture to faces with embeddings.
#ifndef MARVIN_VISION_FACE_PIPELINE_H_
#define MARVIN_VISION_FACE_PIPELINE_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vision/face_detector.h"
#include "vision/face_embedder.h"

namespace marvin::vision {

class FacePipeline {
 public:
  // `detector`: see make_face_detector(). Throws ModelError when a model is missing.
  explicit FacePipeline(const std::string& detector = "blazeface");

  // Every face found, each with its embedding.
  std::vector<Face> faces(const cv::Mat& image_bgr);
  // The largest face of a photo with its embedding. When the detector finds none and
  // `whole_if_none`, the photo is taken as an already cropped face (the ORL photos are).
  std::optional<Face> main_face(const cv::Mat& image_bgr, bool whole_if_none = false);

  FaceDetector& detector() { return *detector_; }
  FaceEmbedder& embedder() { return embedder_; }

 private:
  std::unique_ptr<FaceDetector> detector_;
  FaceEmbedder embedder_;
};

// Enrolment's rule for a photo (`marvin people enroll` and the web page alike): the embedding
// of its one face. Throws std::invalid_argument "photo PHOTO: no face found (detector D)" or
// "photo PHOTO: N faces; give photos of WHO alone" (PHOTO: the file's name as the user gave it).
std::vector<float> lone_face_embedding(FacePipeline& pipeline, const cv::Mat& image_bgr,
                                       const std::string& photo, const std::string& who);

}  // namespace marvin::vision

#endif  // MARVIN_VISION_FACE_PIPELINE_H_
