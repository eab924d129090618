// A small file of named float32 tensors: what the model converter (tools/vision) writes and
// the face embedder reads. Little-endian:
//
//   "MVTENSOR" (8 bytes) | uint32 version = 1 | uint32 tensor count
//   per tensor: uint32 name length | name | uint32 rank | rank x uint32 dims | float32 data
//
// Read errors name the file, the tensor and the byte offset where it went wrong.
#ifndef MARVIN_VISION_TENSOR_FILE_H_
#define MARVIN_VISION_TENSOR_FILE_H_

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace marvin::vision {

struct Tensor {
  std::vector<int> shape;
  std::vector<float> values;
};

using TensorMap = std::map<std::string, Tensor>;

// Throws ModelError (model_files.h) naming the file and what is wrong.
TensorMap read_tensor_file(const std::filesystem::path& path);
// Writes atomically (temporary file + rename); throws std::runtime_error naming the file.
void write_tensor_file(const std::filesystem::path& path, const TensorMap& tensors);

}  // namespace marvin::vision

#endif  // MARVIN_VISION_TENSOR_FILE_H_
