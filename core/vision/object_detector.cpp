#include "vision/object_detector.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "vision/model_files.h"
#include "vision/object_names.h"

namespace marvin::vision {
namespace {

// The graph's outputs (model.json's signature): class scores, then box distances.
const std::vector<std::string> kOutputs = {"Identity",   "Identity_1", "Identity_2",
                                           "Identity_3", "Identity_4", "Identity_5"};

}  // namespace

ObjectDetector::ObjectDetector(const std::filesystem::path& model, float min_score, float nms_iou)
    : path_(model.empty() ? find_model(kNanoDetModel) : model),
      min_score_(min_score),
      nms_iou_(nms_iou),
      net_(load_tfjs_graph(path_, kOutputs)) {}

cv::Mat ObjectDetector::to_blob(const cv::Mat& image_bgr) {
  // NanoDet's own normalisation (its config: BGR, mean 103.53 116.28 123.675, std 57.375
  // 57.12 58.395). human's nanodet.ts feeds RGB / 255 instead; on darknet's photos that
  // finds fewer of the right classes (the dog and bicycle crops come out as cat and toilet).
  cv::Mat blob = cv::dnn::blobFromImage(image_bgr, 1.0, cv::Size(kInputSize, kInputSize),
                                        cv::Scalar(103.53, 116.28, 123.675), /*swapRB=*/false,
                                        /*crop=*/false, CV_32F);
  constexpr float kStd[3] = {57.375f, 57.12f, 58.395f};
  constexpr int kPlane = kInputSize * kInputSize;
  float* p = blob.ptr<float>();
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < kPlane; ++i) p[c * kPlane + i] /= kStd[c];
  }
  return blob;
}

std::vector<cv::Mat> ObjectDetector::forward(const cv::Mat& blob) {
  net_.net.setInput(blob);
  std::vector<cv::Mat> outs;
  net_.net.forward(outs, net_.outputs);
  return outs;
}

std::vector<DetectedObject> ObjectDetector::detect(const cv::Mat& image_bgr) {
  if (image_bgr.empty()) return {};
  const std::vector<cv::Mat> outs = forward(to_blob(image_bgr));
  const float sx = static_cast<float>(image_bgr.cols) / kInputSize;
  const float sy = static_cast<float>(image_bgr.rows) / kInputSize;
  std::map<int, std::vector<cv::Rect2d>> boxes;
  std::map<int, std::vector<float>> scores;
  for (std::size_t level = 0; level < 3; ++level) {
    const cv::Mat& cls = outs[level];
    const cv::Mat& reg = outs[level + 3];
    const int h = cls.size[2], w = cls.size[3], cells = h * w;
    const float stride = static_cast<float>(kInputSize) / static_cast<float>(w);
    const float* c = cls.ptr<float>();
    const float* r = reg.ptr<float>();
    for (int i = 0; i < cells; ++i) {
      int best = 0;
      float best_score = c[i];
      for (int k = 1; k < kCocoClasses; ++k) {
        const float s = c[k * cells + i];
        if (s > best_score) {
          best_score = s;
          best = k;
        }
      }
      if (best_score < min_score_) continue;
      float dist[4];
      for (int side = 0; side < 4; ++side) {  // left, top, right, bottom
        float bins[kRegBins], top = -1e30f;
        for (int b = 0; b < kRegBins; ++b) {
          bins[b] = r[(side * kRegBins + b) * cells + i];
          top = std::max(top, bins[b]);
        }
        float sum = 0, expected = 0;
        for (int b = 0; b < kRegBins; ++b) {
          const float e = std::exp(bins[b] - top);
          sum += e;
          expected += e * static_cast<float>(b);
        }
        dist[side] = expected / sum * stride;
      }
      const float cx = (static_cast<float>(i % w) + 0.5f) * stride;
      const float cy = (static_cast<float>(i / w) + 0.5f) * stride;
      const float x0 = std::max(0.0f, cx - dist[0]) * sx, y0 = std::max(0.0f, cy - dist[1]) * sy;
      const float x1 = std::min(static_cast<float>(kInputSize), cx + dist[2]) * sx;
      const float y1 = std::min(static_cast<float>(kInputSize), cy + dist[3]) * sy;
      boxes[best].emplace_back(x0, y0, x1 - x0, y1 - y0);
      scores[best].push_back(best_score);
    }
  }
  std::vector<DetectedObject> found;
  for (const auto& [k, class_boxes] : boxes) {
    std::vector<int> keep;
    cv::dnn::NMSBoxes(class_boxes, scores[k], min_score_, nms_iou_, keep);
    for (int idx : keep) {
      const auto& b = class_boxes[static_cast<std::size_t>(idx)];
      DetectedObject o;
      o.coco_class = k;
      o.coco = coco_name(k);
      o.label = spoken_name(o.coco);
      o.box = cv::Rect2f(static_cast<float>(b.x), static_cast<float>(b.y),
                         static_cast<float>(b.width), static_cast<float>(b.height));
      o.score = scores[k][static_cast<std::size_t>(idx)];
      found.push_back(std::move(o));
    }
  }
  std::sort(found.begin(), found.end(),
            [](const DetectedObject& a, const DetectedObject& b) { return a.score > b.score; });
  return found;
}

}  // namespace marvin::vision
