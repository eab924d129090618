// marvin-vision-convert: face-api.js's face_recognition_model (weights manifest + uint8
// quantised binary, as npm's @vladmandic/face-api ships it) -> face_recognition.mvt, the
// float32 tensor file FaceEmbedder loads (core/vision/tensor_file.h).
//
//   marvin-vision-convert MANIFEST.json WEIGHTS.bin OUT.mvt
//
// Dequantises (value = q * scale + min, as tfjs's io.decodeWeights does), turns each conv's
// filters from TF's HWIO into OIHW and folds face-api's scale layer (x * w + b after the
// conv's bias) into the conv: W'[o] = W[o] * w[o], b'[o] = bias[o] * w[o] + b[o]. The fully
// connected 256x128 matrix is transposed to 128x256 for OpenCV's InnerProduct.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "vision/tensor_file.h"

namespace {

using marvin::vision::Tensor;
using marvin::vision::TensorMap;

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// name -> tensor in the manifest's own layout (TF's).
TensorMap decode(const std::string& manifest_path, const std::string& bin_path) {
  nlohmann::json manifest;
  try {
    manifest = nlohmann::json::parse(read_all(manifest_path));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(manifest_path + ": not JSON: " + e.what());
  }
  const std::string bin = read_all(bin_path);
  std::size_t pos = 0;
  TensorMap out;
  for (const auto& group : manifest) {
    for (const auto& w : group.at("weights")) {
      const std::string name = w.at("name");
      Tensor t;
      std::size_t n = 1;
      for (int d : w.at("shape")) {
        t.shape.push_back(d);
        n *= static_cast<std::size_t>(d);
      }
      t.values.resize(n);
      if (w.contains("quantization")) {
        const auto& q = w["quantization"];
        if (q.at("dtype") != "uint8") {
          throw std::runtime_error(manifest_path + ": " + name + " is quantised as " +
                                   q.at("dtype").get<std::string>() + ", expected uint8");
        }
        const double scale = q.at("scale"), min = q.at("min");
        if (bin.size() - pos < n) throw std::runtime_error(bin_path + ": truncated in " + name);
        for (std::size_t i = 0; i < n; ++i) {
          t.values[i] = static_cast<float>(static_cast<unsigned char>(bin[pos + i]) * scale + min);
        }
        pos += n;
      } else {
        if (w.at("dtype") != "float32") {
          throw std::runtime_error(manifest_path + ": " + name + " has dtype " +
                                   w.at("dtype").get<std::string>() + ", expected float32");
        }
        if (bin.size() - pos < n * 4) throw std::runtime_error(bin_path + ": truncated in " + name);
        std::memcpy(t.values.data(), bin.data() + pos, n * 4);
        pos += n * 4;
      }
      out.emplace(name, std::move(t));
    }
  }
  if (pos != bin.size()) {
    throw std::runtime_error(bin_path + ": " + std::to_string(bin.size()) + " bytes, the manifest "
                             "describes " + std::to_string(pos));
  }
  return out;
}

const Tensor& get(const TensorMap& m, const std::string& name) {
  auto it = m.find(name);
  if (it == m.end()) throw std::runtime_error("the manifest has no tensor " + name);
  return it->second;
}

void fold_conv(const TensorMap& in, const std::string& prefix, TensorMap& out) {
  const Tensor& f = get(in, prefix + "/conv/filters");  // kh kw in out
  const Tensor& bias = get(in, prefix + "/conv/bias");
  const Tensor& sw = get(in, prefix + "/scale/weights");
  const Tensor& sb = get(in, prefix + "/scale/biases");
  const int kh = f.shape.at(0), kw = f.shape.at(1), ci = f.shape.at(2), co = f.shape.at(3);
  Tensor w{{co, ci, kh, kw}, std::vector<float>(f.values.size())};
  for (int y = 0; y < kh; ++y)
    for (int x = 0; x < kw; ++x)
      for (int i = 0; i < ci; ++i)
        for (int o = 0; o < co; ++o) {
          const float v = f.values[((static_cast<std::size_t>(y) * kw + x) * ci + i) * co + o];
          w.values[((static_cast<std::size_t>(o) * ci + i) * kh + y) * kw + x] =
              v * sw.values.at(static_cast<std::size_t>(o));
        }
  Tensor b{{co}, std::vector<float>(static_cast<std::size_t>(co))};
  for (std::size_t o = 0; o < static_cast<std::size_t>(co); ++o) {
    b.values[o] = bias.values.at(o) * sw.values.at(o) + sb.values.at(o);
  }
  out[prefix + "/weights"] = std::move(w);
  out[prefix + "/bias"] = std::move(b);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s MANIFEST.json WEIGHTS.bin OUT.mvt\n", argv[0]);
    return 2;
  }
  try {
    const TensorMap in = decode(argv[1], argv[2]);
    TensorMap out;
    std::vector<std::string> convs = {"conv32_down"};
    for (const char* block : {"conv32_1", "conv32_2", "conv32_3", "conv64_down", "conv64_1",
                              "conv64_2", "conv64_3", "conv128_down", "conv128_1", "conv128_2",
                              "conv256_down", "conv256_1", "conv256_2", "conv256_down_out"}) {
      convs.push_back(std::string(block) + "/conv1");
      convs.push_back(std::string(block) + "/conv2");
    }
    for (const auto& c : convs) fold_conv(in, c, out);
    const Tensor& fc = get(in, "fc");  // 256 x 128
    const int rows = fc.shape.at(0), cols = fc.shape.at(1);
    Tensor t{{cols, rows}, std::vector<float>(fc.values.size())};
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c)
        t.values[static_cast<std::size_t>(c) * rows + r] =
            fc.values[static_cast<std::size_t>(r) * cols + c];
    out["fc"] = std::move(t);
    marvin::vision::write_tensor_file(argv[3], out);
    std::printf("wrote %s (%zu tensors)\n", argv[3], out.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-vision-convert: %s\n", e.what());
    return 1;
  }
  return 0;
}
