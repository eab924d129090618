// The cameras Marvin ships (camera.h is the interface): a real camera through OpenCV's
// VideoCapture (V4L2), a folder of images and a video file. open_camera() turns the text a
// user writes in a graph or on the command line into one of them.
#ifndef MARVIN_VISION_CAMERAS_H_
#define MARVIN_VISION_CAMERAS_H_

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/videoio.hpp>

#include "vision/camera.h"

namespace marvin::vision {

// A V4L2 device ("/dev/video0") or an index ("0") through cv::VideoCapture. Width, height
// and fps are requests (0 = the device's default); the device may pick the nearest it has.
// Throws CameraError when the device does not open; read() throws when a grab fails
// (unplugged), never returns false.
class VideoCaptureCamera final : public Camera {
 public:
  VideoCaptureCamera(std::string device, int width = 640, int height = 480, double fps = 30);
  bool read(Frame& frame) override;
  std::string describe() const override;

 private:
  std::string device_;
  cv::VideoCapture capture_;
  uint64_t next_index_ = 0;
};

// The images of a folder (jpg, jpeg, png, bmp, pgm, ppm, webp), in name order, as frames
// `frame_interval_us` apart on the camera's clock. Greyscale images become BGR. A file that
// does not decode throws CameraError naming it. `loop` starts over at the end.
class FolderCamera final : public Camera {
 public:
  explicit FolderCamera(const std::filesystem::path& folder, bool loop = false,
                        int64_t frame_interval_us = 100'000);
  bool read(Frame& frame) override;
  std::string describe() const override;
  const std::vector<std::filesystem::path>& files() const { return files_; }

 private:
  std::filesystem::path folder_;
  std::vector<std::filesystem::path> files_;
  bool loop_;
  int64_t interval_us_;
  std::size_t next_ = 0;
  uint64_t next_index_ = 0;
};

// A video file (whatever OpenCV's FFmpeg backend decodes); time from the file's positions.
class VideoFileCamera final : public Camera {
 public:
  explicit VideoFileCamera(const std::filesystem::path& file);
  bool read(Frame& frame) override;
  std::string describe() const override;

 private:
  std::filesystem::path file_;
  cv::VideoCapture capture_;
  double fps_ = 25;
  uint64_t next_index_ = 0;
};

// "folder:PATH", "video:PATH", "device:/dev/video0", "device:0"; without a prefix, an
// existing directory is a folder, an existing regular file a video, anything else a device.
// Throws CameraError naming the spec when it cannot open.
std::unique_ptr<Camera> open_camera(const std::string& spec, int width = 640, int height = 480,
                                    double fps = 30);

// True for the file names FolderCamera reads.
bool is_image_file(const std::filesystem::path& path);

// Reads one photo as 8-bit BGR; throws std::runtime_error naming the file when it is
// missing or does not decode.
cv::Mat read_photo(const std::filesystem::path& path);

}  // namespace marvin::vision

#endif  // MARVIN_VISION_CAMERAS_H_
