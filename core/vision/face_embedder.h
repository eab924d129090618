// FaceEmbedder: 128 numbers per face, close (squared L2) for photos of the same person.
//
// The network is face-api.js's face_recognition_model (dlib's ResNet-34 style metric
// network, MIT), converted by tools/vision/marvin-vision-convert into face_recognition.mvt
// (dequantised, each conv's bias and scale folded into its weights) and built here with
// OpenCV DNN's layer API, layer for layer as face-api.js's FaceRecognitionNet.ts builds it:
//
//   150x150 RGB, minus the mean (122.782, 117.001, 104.298), / 255
//   conv 7x7/2 valid + relu, max pool 3/2 valid
//   residual x3 (32), down + residual x3 (64), down + residual x2 (128),
//   down + residual x2 (256), down (256), global mean, fully connected 256 -> 128
//
// where residual = relu(conv3x3(relu(conv3x3(x))) + x) and down = the same with the first
// conv 3x3/2 valid, the shortcut a 2x2/2 average pool zero-padded to the channels (and, when
// the sizes differ, the conv branch zero-padded by one row and column at the end).
//
// Not thread-safe: one embedder per thread.
#ifndef MARVIN_VISION_FACE_EMBEDDER_H_
#define MARVIN_VISION_FACE_EMBEDDER_H_

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include "vision/face.h"

namespace marvin::vision {

inline constexpr int kEmbeddingSize = 128;
inline constexpr int kFaceChipSize = 150;
// The model id stored with every embedding (face_embeddings.model_id).
inline constexpr const char* kFaceModelId = "face-api-1.7.15/face_recognition_model";

class FaceEmbedder {
 public:
  // Loads `model` (default: find_model(kFaceRecognitionModel)). Throws ModelError naming the
  // file when it is missing, truncated or lacks a tensor with the expected shape.
  explicit FaceEmbedder(const std::filesystem::path& model = {});

  // The embedding of a 150x150 BGR face chip (face_chip()); other sizes are resized.
  std::vector<float> embed_chip(const cv::Mat& chip_bgr);
  // The network on a ready input blob (NCHW float, normalised): for the reference check.
  std::vector<float> embed_blob(const cv::Mat& blob);
  // The normalised NCHW blob of a 150x150 RGB/BGR chip, as face-api.js prepares it.
  static cv::Mat chip_to_blob(const cv::Mat& chip_bgr);

  const std::filesystem::path& model_path() const { return path_; }
  // Bytes of weights held by the network.
  std::size_t weight_bytes() const { return weight_bytes_; }

 private:
  std::filesystem::path path_;
  cv::dnn::Net net_;
  std::size_t weight_bytes_ = 0;
};

// The square region around a detected face the embedder looks at: centred on the box (or
// between eyes and mouth when BlazeFace landmarks are there), rotated so the eyes are level,
// `kFaceChipSize` pixels wide. Pixels outside the frame are black.
cv::Mat face_chip(const cv::Mat& image_bgr, const Face& face, float margin = 1.25f);

float squared_distance(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace marvin::vision

#endif  // MARVIN_VISION_FACE_EMBEDDER_H_
