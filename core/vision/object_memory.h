// ObjectMemory: teach by showing, for things no detector knows ("these are my keys").
//
// Teaching keeps the object's look: ORB keypoints and descriptors of the region shown
// (default: the middle half of the picture, where a user holds a thing up to the camera).
// Finding matches a frame's ORB descriptors against them (2-nearest neighbours, Lowe's
// ratio test 0.75), then fits a homography with RANSAC; the object is there when at least
// kMinInliers matches agree and the projected outline is a sane (convex, not tiny) shape.
//
// Stored in the owner's SQLite store through the per-skill storage of core/data, under the
// owner id "marvin.vision.objects": one key per object ("object:<name>", base64 of a small
// binary record) and "names" (a JSON list). No photo is kept, only the features.
#ifndef MARVIN_VISION_OBJECT_MEMORY_H_
#define MARVIN_VISION_OBJECT_MEMORY_H_

#include <optional>
#include <string>
#include <vector>

#include <opencv2/features2d.hpp>

#include "data/personal_data.h"

namespace marvin::vision {

struct ObjectSighting {
  std::string name;
  std::vector<cv::Point2f> outline;  // the taught region's corners in the frame
  cv::Rect2f box;                    // their bounding box
  int inliers = 0;                   // matches that agree with the homography
};

class ObjectMemory {
 public:
  static constexpr int kMinFeatures = 40;
  static constexpr int kMinInliers = 15;

  explicit ObjectMemory(data::PersonalData& store);

  // Learns (or relearns) `name` from `region` of `image` (empty: the middle half). Throws
  // std::invalid_argument naming the object when the region is outside the picture or too
  // plain (fewer than kMinFeatures features); nothing is stored then.
  void teach(const std::string& name, const cv::Mat& image_bgr, cv::Rect region = {});
  bool forget(const std::string& name);
  std::vector<std::string> names();
  // Where `name` is in the picture, if it is there. Unknown names throw std::invalid_argument.
  std::optional<ObjectSighting> find(const std::string& name, const cv::Mat& image_bgr);
  // Every taught object in view.
  std::vector<ObjectSighting> find_all(const cv::Mat& image_bgr);

 private:
  struct Look {
    cv::Size size;
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
  };
  std::optional<Look> load(const std::string& name);
  std::optional<ObjectSighting> match(const std::string& name, const Look& look,
                                      const std::vector<cv::KeyPoint>& keypoints,
                                      const cv::Mat& descriptors);
  void features(const cv::Mat& image_bgr, std::vector<cv::KeyPoint>& keypoints,
                cv::Mat& descriptors);
  void save_names(const std::vector<std::string>& names);

  data::PersonalData& store_;
  cv::Ptr<cv::ORB> orb_;
};

}  // namespace marvin::vision

#endif  // MARVIN_VISION_OBJECT_MEMORY_H_
