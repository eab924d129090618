// Face detectors: BlazeFace (MediaPipe's detector, ONNX, through OpenCV DNN) and the Haar
// cascade of Viola-Jones (opencv-data), kept selectable as the original robot's baseline.
#ifndef MARVIN_VISION_FACE_DETECTOR_H_
#define MARVIN_VISION_FACE_DETECTOR_H_

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>
#include <opencv2/objdetect.hpp>

#include "vision/face.h"

namespace marvin::vision {

class FaceDetector {
 public:
  virtual ~FaceDetector() = default;
  // Faces in an 8-bit BGR image, most confident first.
  virtual std::vector<Face> detect(const cv::Mat& image_bgr) = 0;
  virtual std::string name() const = 0;
};

// BlazeFace, "back" (256x256 input, faces from about 1/16 of the picture: a room) or
// "front" (128x128, selfie distance). The picture is letterboxed to a square, so nothing is
// cut off. The 896 anchors (16x16 cells x 2 + 8x8 cells x 6) are decoded here as keijiro's
// Postprocess1 shader does; overlapping boxes are merged by non-maximum suppression.
class BlazeFaceDetector final : public FaceDetector {
 public:
  enum class Range { kBack256, kFront128 };
  // Throws ModelError naming the file when it is missing or OpenCV cannot read it.
  explicit BlazeFaceDetector(Range range = Range::kBack256, float min_score = 0.6f,
                             const std::filesystem::path& model = {});
  std::vector<Face> detect(const cv::Mat& image_bgr) override;
  std::string name() const override;

 private:
  Range range_;
  int size_;
  float min_score_;
  cv::dnn::Net net_;
  std::vector<std::string> outputs_;
};

// OpenCV's Haar cascade (haarcascade_frontalface_default.xml from opencv-data).
class HaarFaceDetector final : public FaceDetector {
 public:
  explicit HaarFaceDetector(const std::filesystem::path& cascade = {});
  std::vector<Face> detect(const cv::Mat& image_bgr) override;
  std::string name() const override { return "haar"; }

 private:
  cv::CascadeClassifier cascade_;
};

// "blazeface" (= "blazeface-back"), "blazeface-front" or "haar".
std::unique_ptr<FaceDetector> make_face_detector(const std::string& kind);

}  // namespace marvin::vision

#endif  // MARVIN_VISION_FACE_DETECTOR_H_
