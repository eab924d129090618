#include "vision/face_embedder.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "vision/model_files.h"
#include "vision/tensor_file.h"

namespace marvin::vision {
namespace {

// The residual blocks of FaceRecognitionNet.ts, in order: name, output channels, down?
struct Block {
  const char* name;
  int channels;
  bool down;
};
constexpr Block kBlocks[] = {
    {"conv32_1", 32, false},      {"conv32_2", 32, false},      {"conv32_3", 32, false},
    {"conv64_down", 64, true},    {"conv64_1", 64, false},      {"conv64_2", 64, false},
    {"conv64_3", 64, false},      {"conv128_down", 128, true},  {"conv128_1", 128, false},
    {"conv128_2", 128, false},    {"conv256_down", 256, true},  {"conv256_1", 256, false},
    {"conv256_2", 256, false},    {"conv256_down_out", 256, true},
};

class NetBuilder {
 public:
  NetBuilder(cv::dnn::Net& net, TensorMap& tensors, const std::filesystem::path& path)
      : net_(net), tensors_(tensors), path_(path) {}

  // Conv (weights OIHW + bias, the converter folded face-api's scale layer in) + optional ReLU.
  int conv(const std::string& name, int input, int kernel, int stride, int pad, int in_ch,
           int out_ch, bool relu) {
    const Tensor& w = tensor(name + "/weights", {out_ch, in_ch, kernel, kernel});
    const Tensor& b = tensor(name + "/bias", {out_ch});
    cv::dnn::LayerParams p;
    p.set("kernel_size", kernel);
    p.set("stride", stride);
    p.set("pad", pad);
    p.set("num_output", out_ch);
    p.set("bias_term", true);
    const int shape[] = {out_ch, in_ch, kernel, kernel};
    p.blobs.push_back(cv::Mat(4, shape, CV_32F, const_cast<float*>(w.values.data())).clone());
    p.blobs.push_back(cv::Mat(1, out_ch, CV_32F, const_cast<float*>(b.values.data())).clone());
    bytes_ += (w.values.size() + b.values.size()) * sizeof(float);
    int id = add(name, "Convolution", p, {input});
    if (relu) id = this->relu(name + "/relu", id);
    return id;
  }
  int relu(const std::string& name, int input) {
    cv::dnn::LayerParams p;
    return add(name, "ReLU", p, {input});
  }
  int pool(const std::string& name, int input, const char* kind, int kernel, int stride) {
    cv::dnn::LayerParams p;
    p.set("pool", kind);
    p.set("kernel_size", kernel);
    p.set("stride", stride);
    p.set("pad", 0);
    p.set("ceil_mode", false);  // TF's 'valid'
    return add(name, "Pooling", p, {input});
  }
  int sum(const std::string& name, int a, int b) {
    cv::dnn::LayerParams p;
    p.set("operation", "sum");
    return add(name, "Eltwise", p, {a, b});
  }
  // Zeros appended at the end of channels, rows and columns (NCHW).
  int pad_end(const std::string& name, int input, int channels, int rows, int cols) {
    cv::dnn::LayerParams p;
    const int paddings[] = {0, 0, 0, channels, 0, rows, 0, cols};
    p.set("paddings", cv::dnn::DictValue::arrayInt(paddings, 8));
    p.set("value", 0.0);
    return add(name, "Padding", p, {input});
  }
  int global_mean(const std::string& name, int input) {
    cv::dnn::LayerParams p;
    p.set("pool", "ave");
    p.set("global_pooling", true);
    return add(name, "Pooling", p, {input});
  }
  int fully_connected(const std::string& name, int input, int in, int out) {
    const Tensor& w = tensor(name, {out, in});
    cv::dnn::LayerParams p;
    p.set("num_output", out);
    p.set("bias_term", false);
    p.set("axis", 1);
    p.blobs.push_back(cv::Mat(out, in, CV_32F, const_cast<float*>(w.values.data())).clone());
    bytes_ += w.values.size() * sizeof(float);
    return add(name, "InnerProduct", p, {input});
  }
  std::size_t bytes() const { return bytes_; }

 private:
  const Tensor& tensor(const std::string& name, const std::vector<int>& shape) {
    auto it = tensors_.find(name);
    if (it == tensors_.end()) {
      throw ModelError("model " + path_.string() + ": tensor " + name +
                       " is missing (not a face recognition model, or from another converter "
                       "version): run scripts/setup again");
    }
    if (it->second.shape != shape) {
      std::string want, got;
      for (int d : shape) want += (want.empty() ? "" : "x") + std::to_string(d);
      for (int d : it->second.shape) got += (got.empty() ? "" : "x") + std::to_string(d);
      throw ModelError("model " + path_.string() + ": tensor " + name + " has shape " + got +
                       ", expected " + want);
    }
    return it->second;
  }
  int add(const std::string& name, const std::string& type, cv::dnn::LayerParams& p,
          std::initializer_list<int> inputs) {
    p.name = name;
    p.type = type;
    const int id = net_.addLayer(name, type, p);
    int port = 0;
    for (int in : inputs) net_.connect(in, 0, id, port++);
    return id;
  }

  cv::dnn::Net& net_;
  TensorMap& tensors_;
  const std::filesystem::path& path_;
  std::size_t bytes_ = 0;
};

}  // namespace

FaceEmbedder::FaceEmbedder(const std::filesystem::path& model)
    : path_(model.empty() ? find_model(kFaceRecognitionModel) : model) {
  TensorMap tensors = read_tensor_file(path_);
  NetBuilder b(net_, tensors, path_);
  net_.setInputsNames({"data"});
  // Shapes (150 input): 72 after the first conv, 35 after the pool, 17, 8, 3 -> 4, 1 -> 2.
  int x = b.conv("conv32_down", 0, 7, 2, 0, 3, 32, true);
  x = b.pool("pool1", x, "max", 3, 2);
  int channels = 32;
  int size = 35;
  for (const Block& blk : kBlocks) {
    const std::string n = blk.name;
    if (!blk.down) {
      int y = b.conv(n + "/conv1", x, 3, 1, 1, channels, blk.channels, true);
      y = b.conv(n + "/conv2", y, 3, 1, 1, blk.channels, blk.channels, false);
      x = b.relu(n + "/out", b.sum(n + "/sum", y, x));
      continue;
    }
    int y = b.conv(n + "/conv1", x, 3, 2, 0, channels, blk.channels, true);
    y = b.conv(n + "/conv2", y, 3, 1, 1, blk.channels, blk.channels, false);
    const int conv_size = (size - 3) / 2 + 1;
    const int pool_size = size / 2;
    if (conv_size != pool_size) y = b.pad_end(n + "/pad", y, 0, 1, 1);
    int shortcut = b.pool(n + "/avg", x, "ave", 2, 2);
    if (blk.channels != channels) {
      shortcut = b.pad_end(n + "/zeros", shortcut, blk.channels - channels, 0, 0);
    }
    x = b.relu(n + "/out", b.sum(n + "/sum", y, shortcut));
    channels = blk.channels;
    size = pool_size;
  }
  x = b.global_mean("mean", x);
  b.fully_connected("fc", x, 256, kEmbeddingSize);
  weight_bytes_ = b.bytes();
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
}

cv::Mat FaceEmbedder::chip_to_blob(const cv::Mat& chip_bgr) {
  cv::Mat chip = chip_bgr;
  if (chip.cols != kFaceChipSize || chip.rows != kFaceChipSize) {
    cv::resize(chip_bgr, chip, cv::Size(kFaceChipSize, kFaceChipSize), 0, 0, cv::INTER_LINEAR);
  }
  // swapRB: the network wants RGB; mean in RGB order after the swap.
  return cv::dnn::blobFromImage(chip, 1.0 / 255.0, cv::Size(), cv::Scalar(122.782, 117.001, 104.298),
                                /*swapRB=*/true, /*crop=*/false, CV_32F);
}

std::vector<float> FaceEmbedder::embed_blob(const cv::Mat& blob) {
  net_.setInput(blob, "data");
  cv::Mat out = net_.forward();
  const float* p = out.ptr<float>();
  return std::vector<float>(p, p + kEmbeddingSize);
}

std::vector<float> FaceEmbedder::embed_chip(const cv::Mat& chip_bgr) {
  return embed_blob(chip_to_blob(chip_bgr));
}

cv::Mat face_chip(const cv::Mat& image_bgr, const Face& face, float margin) {
  cv::Point2f centre(face.box.x + face.box.width / 2, face.box.y + face.box.height / 2);
  double angle = 0;
  if (face.landmarks.size() >= 4) {
    const cv::Point2f right_eye = face.landmarks[0], left_eye = face.landmarks[1];
    const cv::Point2f mouth = face.landmarks[3];
    const cv::Point2f eyes = (right_eye + left_eye) * 0.5f;
    centre = (eyes + mouth) * 0.5f;
    angle = std::atan2(left_eye.y - right_eye.y, left_eye.x - right_eye.x) * 180.0 / CV_PI;
  }
  const float side = std::max(face.box.width, face.box.height) * margin;
  const double scale = kFaceChipSize / std::max(side, 1.0f);
  cv::Mat m = cv::getRotationMatrix2D(centre, angle, scale);
  m.at<double>(0, 2) += kFaceChipSize / 2.0 - centre.x;
  m.at<double>(1, 2) += kFaceChipSize / 2.0 - centre.y;
  cv::Mat chip;
  cv::warpAffine(image_bgr, chip, m, cv::Size(kFaceChipSize, kFaceChipSize), cv::INTER_LINEAR,
                 cv::BORDER_CONSTANT, cv::Scalar());
  return chip;
}

float squared_distance(const std::vector<float>& a, const std::vector<float>& b) {
  float d = 0;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) d += (a[i] - b[i]) * (a[i] - b[i]);
  return d;
}

}  // namespace marvin::vision
