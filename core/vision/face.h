// What the face pipeline says about one face in one frame, and the packet that carries the
// faces of a frame through the vision graph (detector -> embedder -> identifier).
#ifndef MARVIN_VISION_FACE_H_
#define MARVIN_VISION_FACE_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace marvin::vision {

struct Face {
  cv::Rect2f box;                       // in frame pixels
  float score = 0;                      // detector confidence, 0..1 (Haar: 1)
  std::vector<cv::Point2f> landmarks;   // BlazeFace: right eye, left eye, nose, mouth,
                                        // right ear, left ear (the person's sides); Haar: none
  std::vector<float> embedding;         // 128 numbers once the embedder ran
  std::string name;                     // once identified; empty = someone unknown
  float distance = -1;                  // squared L2 to the nearest enrolled embedding
};

// The faces of one frame. `image` shares the frame's pixels (cv::Mat is reference counted);
// nodes must not write into it.
struct FaceList {
  cv::Mat image;
  uint64_t frame_index = 0;
  std::vector<Face> faces;
};

}  // namespace marvin::vision

#endif  // MARVIN_VISION_FACE_H_
