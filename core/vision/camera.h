// The one camera interface of Marvin: a real camera (OpenCV VideoCapture), a folder of
// images or a video file, and the simulated home's camera all implement it, so the vision
// graph and the skills never know which one they look through.
//
// Life cycle: construct (opening may throw CameraError naming the device), then read()
// repeatedly from one thread at a time. A camera is not safe for concurrent read() calls.
#ifndef MARVIN_VISION_CAMERA_H_
#define MARVIN_VISION_CAMERA_H_

#include <cstdint>
#include <stdexcept>
#include <string>

#include <opencv2/core/mat.hpp>

namespace marvin::vision {

// One picture from a camera.
struct Frame {
  cv::Mat image;         // 8-bit BGR (CV_8UC3), the camera's native size
  int64_t time_us = 0;   // when it was taken: the camera's clock, microseconds
  uint64_t index = 0;    // 0, 1, 2, ... in the order this camera produced them
};

// A camera that failed to open, failed while reading, or vanished (unplugged). The
// message names the device ("camera /dev/video0: ...") and what went wrong.
class CameraError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Camera {
 public:
  virtual ~Camera() = default;

  // Takes the next picture into `frame` (reusing its buffer when the size matches).
  // Returns true with a new frame; false when a finite source (a folder, a video file)
  // has no more frames. Throws CameraError when the device fails or disappears; the
  // caller may construct the camera again to retry.
  virtual bool read(Frame& frame) = 0;

  // What this camera is, for logs and error messages: "v4l2 /dev/video0 640x480@30",
  // "folder photos/ (12 images)", "simulated camera (head of the robot)".
  virtual std::string describe() const = 0;
};

}  // namespace marvin::vision

#endif  // MARVIN_VISION_CAMERA_H_
