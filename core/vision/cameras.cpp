#include "vision/cameras.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <system_error>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace marvin::vision {
namespace {

int64_t steady_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Cameras deliver BGR; greyscale (PGM) and BGRA images are converted so nodes see one format.
void to_bgr(const cv::Mat& in, cv::Mat& out) {
  if (in.channels() == 1) {
    cv::cvtColor(in, out, cv::COLOR_GRAY2BGR);
  } else if (in.channels() == 4) {
    cv::cvtColor(in, out, cv::COLOR_BGRA2BGR);
  } else {
    in.copyTo(out);
  }
}

bool is_number(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
}

}  // namespace

bool is_image_file(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); });
  return ext == ".jpg" || ext == ".jpeg" || ext == ".png" || ext == ".bmp" || ext == ".pgm" ||
         ext == ".ppm" || ext == ".webp";
}

cv::Mat read_photo(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw std::runtime_error("photo " + path.string() + ": no such file");
  }
  cv::Mat raw = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (raw.empty() || raw.depth() != CV_8U) {
    throw std::runtime_error("photo " + path.string() +
                             ": not an image OpenCV can decode (expected 8-bit JPEG, PNG, BMP, "
                             "PGM/PPM or WebP)");
  }
  cv::Mat bgr;
  to_bgr(raw, bgr);
  return bgr;
}

// ---- VideoCaptureCamera ----

VideoCaptureCamera::VideoCaptureCamera(std::string device, int width, int height, double fps)
    : device_(std::move(device)) {
  const bool opened = is_number(device_) ? capture_.open(std::stoi(device_), cv::CAP_V4L2)
                                         : capture_.open(device_, cv::CAP_V4L2);
  if (!opened || !capture_.isOpened()) {
    throw CameraError("camera " + device_ + ": cannot open the video device (is it plugged in, "
                      "and may this user read it?)");
  }
  if (width > 0) capture_.set(cv::CAP_PROP_FRAME_WIDTH, width);
  if (height > 0) capture_.set(cv::CAP_PROP_FRAME_HEIGHT, height);
  if (fps > 0) capture_.set(cv::CAP_PROP_FPS, fps);
}

bool VideoCaptureCamera::read(Frame& frame) {
  cv::Mat raw;
  if (!capture_.read(raw) || raw.empty()) {
    throw CameraError("camera " + device_ + ": reading a frame failed (device unplugged?)");
  }
  to_bgr(raw, frame.image);
  frame.time_us = steady_us();
  frame.index = next_index_++;
  return true;
}

std::string VideoCaptureCamera::describe() const {
  return "v4l2 " + device_ + " " +
         std::to_string(static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_WIDTH))) + "x" +
         std::to_string(static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_HEIGHT))) + "@" +
         std::to_string(static_cast<int>(capture_.get(cv::CAP_PROP_FPS)));
}

// ---- FolderCamera ----

FolderCamera::FolderCamera(const std::filesystem::path& folder, bool loop,
                           int64_t frame_interval_us)
    : folder_(folder), loop_(loop), interval_us_(frame_interval_us) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) {
    throw CameraError("camera folder " + folder.string() + ": not a directory");
  }
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    if (entry.is_regular_file() && is_image_file(entry.path())) files_.push_back(entry.path());
  }
  if (ec) throw CameraError("camera folder " + folder.string() + ": " + ec.message());
  std::sort(files_.begin(), files_.end());
  if (files_.empty()) {
    throw CameraError("camera folder " + folder.string() +
                      ": no images (expected .jpg, .png, .bmp, .pgm, .ppm or .webp files)");
  }
}

bool FolderCamera::read(Frame& frame) {
  if (next_ >= files_.size()) {
    if (!loop_) return false;
    next_ = 0;
  }
  const std::filesystem::path& path = files_[next_++];
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw CameraError("camera folder " + folder_.string() + ": " + path.filename().string() +
                      " vanished");
  }
  cv::Mat raw = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (raw.empty() || raw.depth() != CV_8U) {
    throw CameraError("camera folder " + folder_.string() + ": " + path.filename().string() +
                      " is not an image OpenCV can decode");
  }
  to_bgr(raw, frame.image);
  frame.index = next_index_++;
  frame.time_us = static_cast<int64_t>(frame.index) * interval_us_;
  return true;
}

std::string FolderCamera::describe() const {
  return "folder " + folder_.string() + " (" + std::to_string(files_.size()) + " images)";
}

// ---- VideoFileCamera ----

VideoFileCamera::VideoFileCamera(const std::filesystem::path& file) : file_(file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec) || !capture_.open(file.string()) ||
      !capture_.isOpened()) {
    throw CameraError("camera video " + file.string() + ": cannot open (missing, or a format "
                      "OpenCV's video backend does not read)");
  }
  const double fps = capture_.get(cv::CAP_PROP_FPS);
  if (fps > 0) fps_ = fps;
}

bool VideoFileCamera::read(Frame& frame) {
  cv::Mat raw;
  if (!capture_.read(raw) || raw.empty()) return false;
  to_bgr(raw, frame.image);
  frame.index = next_index_++;
  frame.time_us = static_cast<int64_t>(static_cast<double>(frame.index) * 1e6 / fps_);
  return true;
}

std::string VideoFileCamera::describe() const {
  return "video " + file_.string() + " @" + std::to_string(static_cast<int>(fps_));
}

std::unique_ptr<Camera> open_camera(const std::string& spec, int width, int height, double fps) {
  auto starts = [&](const char* prefix) { return spec.rfind(prefix, 0) == 0; };
  if (starts("folder:")) return std::make_unique<FolderCamera>(spec.substr(7));
  if (starts("video:")) return std::make_unique<VideoFileCamera>(spec.substr(6));
  if (starts("device:")) {
    return std::make_unique<VideoCaptureCamera>(spec.substr(7), width, height, fps);
  }
  std::error_code ec;
  if (std::filesystem::is_directory(spec, ec)) return std::make_unique<FolderCamera>(spec);
  if (std::filesystem::is_regular_file(spec, ec) && !starts("/dev/")) {
    return std::make_unique<VideoFileCamera>(spec);
  }
  if (spec.empty()) throw CameraError("camera: no camera given (expected folder:, video: or device:)");
  return std::make_unique<VideoCaptureCamera>(spec, width, height, fps);
}

}  // namespace marvin::vision
