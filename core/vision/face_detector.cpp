#include "vision/face_detector.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "vision/model_files.h"

namespace marvin::vision {
namespace {

float sigmoid(float x) {
  x = std::clamp(x, -100.0f, 100.0f);
  return 1.0f / (1.0f + std::exp(-x));
}

}  // namespace

BlazeFaceDetector::BlazeFaceDetector(Range range, float min_score,
                                     const std::filesystem::path& model)
    : range_(range), size_(range == Range::kBack256 ? 256 : 128), min_score_(min_score) {
  const std::filesystem::path path =
      !model.empty() ? model
                     : find_model(range == Range::kBack256 ? kBlazeFaceBackModel
                                                           : kBlazeFaceFrontModel);
  try {
    net_ = cv::dnn::readNetFromONNX(path.string());
  } catch (const cv::Exception& e) {
    throw ModelError("model " + path.string() + ": OpenCV cannot read it as ONNX (" +
                     std::string(e.err) + "): run scripts/setup again");
  }
  if (net_.empty()) throw ModelError("model " + path.string() + ": empty network");
  outputs_ = net_.getUnconnectedOutLayersNames();
  if (outputs_.size() != 4) {
    throw ModelError("model " + path.string() + ": " + std::to_string(outputs_.size()) +
                     " outputs, expected 4 (scores and boxes of the 16x16 and 8x8 cells)");
  }
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
}

std::string BlazeFaceDetector::name() const {
  return range_ == Range::kBack256 ? "blazeface-back" : "blazeface-front";
}

std::vector<Face> BlazeFaceDetector::detect(const cv::Mat& image_bgr) {
  if (image_bgr.empty()) return {};
  // Letterbox into a square at the top left, then scale to the network's size.
  const int side = std::max(image_bgr.cols, image_bgr.rows);
  const float to_image = static_cast<float>(side) / static_cast<float>(size_);
  cv::Mat square(side, side, CV_8UC3, cv::Scalar());
  image_bgr.copyTo(square(cv::Rect(0, 0, image_bgr.cols, image_bgr.rows)));
  cv::Mat small, rgb, input;
  cv::resize(square, small, cv::Size(size_, size_), 0, 0, cv::INTER_AREA);
  cv::cvtColor(small, rgb, cv::COLOR_BGR2RGB);
  rgb.convertTo(input, CV_32FC3, 1.0 / 127.5, -1.0);
  const int dims[] = {1, size_, size_, 3};  // the model takes channels last
  net_.setInput(cv::Mat(4, dims, CV_32F, input.ptr<float>()));
  std::vector<cv::Mat> outs;
  net_.forward(outs, outputs_);
  // Which output is which, by size: scores have 1 number per anchor, boxes 16; the 16x16
  // cells have 512 anchors, the 8x8 cells 384.
  std::vector<float> s(896), b(896 * 16);
  for (const cv::Mat& out : outs) {
    const float* p = out.ptr<float>();
    switch (out.total()) {
      case 512: std::copy(p, p + 512, s.begin()); break;
      case 384: std::copy(p, p + 384, s.begin() + 512); break;
      case 512 * 16: std::copy(p, p + 512 * 16, b.begin()); break;
      case 384 * 16: std::copy(p, p + 384 * 16, b.begin() + 512 * 16); break;
      default:
        throw ModelError("BlazeFace model: an output of " + std::to_string(out.total()) +
                         " numbers, expected 512, 384, 8192 or 6144");
    }
  }
  std::vector<Face> found;
  std::vector<cv::Rect2d> rects;
  std::vector<float> confidences;
  const float scale = 1.0f / static_cast<float>(size_);
  int anchor = 0;
  for (const auto& [cells, per_cell] : {std::pair{16, 2}, std::pair{8, 6}}) {
    for (int y = 0; y < cells; ++y) {
      for (int x = 0; x < cells; ++x) {
        const float ax = (static_cast<float>(x) + 0.5f) / static_cast<float>(cells);
        const float ay = (static_cast<float>(y) + 0.5f) / static_cast<float>(cells);
        for (int k = 0; k < per_cell; ++k, ++anchor) {
          const float score = sigmoid(s[anchor]);
          if (score < min_score_) continue;
          const float* r = b.data() + anchor * 16;
          const float cx = (ax + r[0] * scale) * static_cast<float>(size_) * to_image;
          const float cy = (ay + r[1] * scale) * static_cast<float>(size_) * to_image;
          const float w = r[2] * scale * static_cast<float>(size_) * to_image;
          const float h = r[3] * scale * static_cast<float>(size_) * to_image;
          Face f;
          f.box = cv::Rect2f(cx - w / 2, cy - h / 2, w, h);
          f.score = score;
          for (int p = 0; p < 6; ++p) {
            f.landmarks.emplace_back((ax + r[4 + 2 * p] * scale) * static_cast<float>(side),
                                     (ay + r[5 + 2 * p] * scale) * static_cast<float>(side));
          }
          rects.emplace_back(f.box);
          confidences.push_back(score);
          found.push_back(std::move(f));
        }
      }
    }
  }
  std::vector<int> keep;
  cv::dnn::NMSBoxes(rects, confidences, min_score_, 0.3f, keep);
  std::vector<Face> faces;
  for (int i : keep) {
    Face f = found[static_cast<std::size_t>(i)];
    f.box &= cv::Rect2f(0, 0, static_cast<float>(image_bgr.cols),
                        static_cast<float>(image_bgr.rows));
    if (f.box.area() > 0) faces.push_back(std::move(f));
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& c) { return a.score > c.score; });
  return faces;
}

HaarFaceDetector::HaarFaceDetector(const std::filesystem::path& cascade) {
  const std::filesystem::path path = cascade.empty() ? kHaarFrontalFace : cascade;
  if (!cascade_.load(path.string())) {
    throw ModelError("Haar cascade " + path.string() +
                     ": missing or not a cascade (it comes with Debian's opencv-data: run "
                     "scripts/setup)");
  }
}

std::vector<Face> HaarFaceDetector::detect(const cv::Mat& image_bgr) {
  if (image_bgr.empty()) return {};
  cv::Mat grey;
  cv::cvtColor(image_bgr, grey, cv::COLOR_BGR2GRAY);
  cv::equalizeHist(grey, grey);
  std::vector<cv::Rect> rects;
  cascade_.detectMultiScale(grey, rects, 1.1, 4, 0, cv::Size(24, 24));
  std::vector<Face> faces;
  for (const auto& r : rects) {
    Face f;
    f.box = cv::Rect2f(r);
    f.score = 1;
    faces.push_back(std::move(f));
  }
  std::sort(faces.begin(), faces.end(),
            [](const Face& a, const Face& c) { return a.box.area() > c.box.area(); });
  return faces;
}

std::unique_ptr<FaceDetector> make_face_detector(const std::string& kind) {
  if (kind == "blazeface" || kind == "blazeface-back") {
    return std::make_unique<BlazeFaceDetector>(BlazeFaceDetector::Range::kBack256);
  }
  if (kind == "blazeface-front") {
    return std::make_unique<BlazeFaceDetector>(BlazeFaceDetector::Range::kFront128);
  }
  if (kind == "haar") return std::make_unique<HaarFaceDetector>();
  throw std::invalid_argument("face detector \"" + kind +
                              "\": expected blazeface, blazeface-front or haar");
}

}  // namespace marvin::vision
