// A small reader for the ONNX files of the embedding wake word (issue 21): the graph's nodes
// (operator, inputs, outputs, attributes) and its constant tensors, nothing more.
//
// ONNX is protobuf; this reads the protobuf wire format directly (varints and length-delimited
// fields of ModelProto -> GraphProto -> NodeProto / AttributeProto / TensorProto), so Marvin
// needs no protobuf library and no conversion step: the runtime loads the files npm ships
// (scripts/fetch-kws-models). Only float32 and int64 tensors are kept, which is all the two
// graphs hold. Unknown fields are skipped, as protobuf readers do.
//
// Errors are OnnxError; the message names the file, what was being read and the byte offset.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace marvin::perception::kws {

class OnnxError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct OnnxTensor {
  std::vector<std::int64_t> dims;
  std::vector<float> floats;        // data_type FLOAT
  std::vector<std::int64_t> ints;   // data_type INT64 / INT32
  std::size_t size() const;         // product of dims (1 for a scalar)
};

struct OnnxAttribute {
  float f = 0.0f;
  std::int64_t i = 0;
  std::string s;
  std::vector<float> floats;
  std::vector<std::int64_t> ints;
  OnnxTensor t;
};

struct OnnxNode {
  std::string op_type;
  std::vector<std::string> inputs;
  std::vector<std::string> outputs;
  std::map<std::string, OnnxAttribute> attributes;

  // The attribute's ints, or `fallback` when the node does not have it.
  std::vector<std::int64_t> ints(const std::string& name,
                                 std::vector<std::int64_t> fallback = {}) const;
};

struct OnnxGraph {
  std::filesystem::path file;
  std::vector<OnnxNode> nodes;
  // Initializers and the outputs of Constant nodes, by name.
  std::map<std::string, OnnxTensor> constants;

  // The named constant; throws OnnxError naming the file and the tensor when it is missing.
  const OnnxTensor& constant(const std::string& name) const;
};

// Reads an .onnx file. Throws OnnxError when it is missing, truncated or malformed.
OnnxGraph read_onnx(const std::filesystem::path& file);

}  // namespace marvin::perception::kws
