#include "vision/tfjs_graph.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <system_error>

#include "vision/model_files.h"

namespace marvin::vision {
namespace {

using nlohmann::json;

// IEEE half -> float (tensorflowjs_converter's float16 quantisation).
float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = (h & 0x8000u) << 16;
  std::uint32_t exp = (h >> 10) & 0x1fu;
  std::uint32_t mant = h & 0x3ffu;
  std::uint32_t bits;
  if (exp == 0) {
    if (mant == 0) {
      bits = sign;
    } else {  // subnormal: normalise
      exp = 127 - 15 + 1;
      while ((mant & 0x400u) == 0) {
        mant <<= 1;
        --exp;
      }
      bits = sign | (exp << 23) | ((mant & 0x3ffu) << 13);
    }
  } else if (exp == 31) {
    bits = sign | 0x7f800000u | (mant << 13);
  } else {
    bits = sign | ((exp + 127 - 15) << 23) | (mant << 13);
  }
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// A constant of the graph (weights, shapes, axes), as floats; ints are exact up to 2^24.
struct Constant {
  std::vector<int> shape;
  std::vector<float> values;
};

// A tensor flowing through the OpenCV network. In memory always NCHW; `nhwc` says how the
// graph indexes it. A pending pad is a Pad not yet given to a layer (a convolution takes it
// as its own padding; anything else gets a Padding layer).
struct Tensor {
  int layer = 0;
  int port = 0;
  bool nhwc = false;
  int channels = 0;
  bool padded = false;
  std::array<int, 8> pads{};  // NCHW order: before, after for N, C, H, W
  float pad_value = 0;
};

struct Value {
  bool constant = false;
  Constant c;
  Tensor t;
};

std::string shape_text(const std::vector<int>& shape) {
  std::string s;
  for (int d : shape) s += (s.empty() ? "" : "x") + std::to_string(d);
  return s.empty() ? "scalar" : s;
}

class GraphBuilder {
 public:
  GraphBuilder(const std::filesystem::path& path, TfjsNet& out) : path_(path), out_(out) {
    std::ifstream in(path);
    if (!in) {
      throw ModelError("vision model " + path.string() +
                       " cannot be read: run scripts/setup, then build, to fetch the models");
    }
    json model;
    try {
      model = json::parse(in);
    } catch (const json::exception& e) {
      throw ModelError("model " + path.string() + " is not a TF.js model.json: " + e.what());
    }
    if (!model.contains("modelTopology") || !model["modelTopology"].contains("node") ||
        !model.contains("weightsManifest")) {
      throw ModelError("model " + path.string() +
                       ": no modelTopology.node or weightsManifest (not a TF.js graph model)");
    }
    for (const auto& node : model["modelTopology"]["node"]) {
      const std::string name = node.value("name", "");
      nodes_[name] = node;
      for (const auto& in_name : node.value("input", json::array())) {
        consumers_[base_name(in_name.get<std::string>())].push_back(name);
      }
    }
    read_weights(model["weightsManifest"]);
  }

  void build(const std::vector<std::string>& outputs) {
    for (const auto& name : outputs) {
      std::string node = name;
      // Look through a final re-layout (Identity -> Transpose -> Reshape) to the 4-d tensor.
      for (;;) {
        const json& n = node_of(base_name(node));
        const std::string op = n["op"];
        if (op != "Identity" && op != "Transpose" && op != "Reshape") break;
        node = n["input"][0];
      }
      const Value& v = resolve(node);
      if (v.constant) fail(node, "is a constant, not a computed output");
      const Tensor t = materialize(v.t, node);
      // An Identity layer gives every output a name of its own (Slice has several ports).
      cv::dnn::LayerParams p;
      const int id = add(name + "/out", "Identity", p, {t});
      out_.outputs.push_back(name + "/out");
      (void)id;
    }
  }

 private:
  [[noreturn]] void fail(const std::string& node, const std::string& what) const {
    throw ModelError("model " + path_.string() + ": node " + node + " " + what);
  }

  static std::string base_name(const std::string& input) {
    const auto colon = input.find(':');
    std::string s = colon == std::string::npos ? input : input.substr(0, colon);
    if (!s.empty() && s[0] == '^') s.erase(0, 1);
    return s;
  }
  static int port_of(const std::string& input) {
    const auto colon = input.find(':');
    return colon == std::string::npos ? 0 : std::stoi(input.substr(colon + 1));
  }

  const json& node_of(const std::string& name) const {
    auto it = nodes_.find(name);
    if (it == nodes_.end()) {
      throw ModelError("model " + path_.string() + ": no node named " + name);
    }
    return it->second;
  }

  void read_weights(const json& manifest) {
    const auto dir = path_.parent_path();
    for (const auto& group : manifest) {
      std::string data;
      for (const auto& shard : group.value("paths", json::array())) {
        const auto file = dir / shard.get<std::string>();
        std::ifstream in(file, std::ios::binary);
        if (!in) {
          throw ModelError("vision model weights " + file.string() +
                           " cannot be read: run scripts/setup, then build, to fetch the models");
        }
        data.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      }
      std::size_t offset = 0;
      for (const auto& w : group.value("weights", json::array())) {
        Constant c;
        std::size_t count = 1;
        for (const auto& d : w.value("shape", json::array())) {
          c.shape.push_back(d.get<int>());
          count *= static_cast<std::size_t>(d.get<int>());
        }
        const std::string dtype = w.value("dtype", "float32");
        std::string stored = dtype;
        float scale = 1, min = 0;
        if (w.contains("quantization") && w["quantization"].is_object()) {
          const auto& q = w["quantization"];
          stored = q.value("dtype", dtype);
          scale = q.value("scale", 1.0f);
          min = q.value("min", 0.0f);
        }
        const std::size_t width = stored == "float16" || stored == "uint16" ? 2
                                  : stored == "uint8"                       ? 1
                                                                            : 4;
        if (offset + count * width > data.size()) {
          throw ModelError("model weights of " + path_.string() +
                           " are truncated: " + std::to_string(data.size()) + " bytes, weight " +
                           w.value("name", "") + " needs bytes up to " +
                           std::to_string(offset + count * width) + ": run scripts/setup again");
        }
        c.values.resize(count);
        const char* p = data.data() + offset;
        for (std::size_t i = 0; i < count; ++i) {
          if (stored == "float16") {
            std::uint16_t h;
            std::memcpy(&h, p + 2 * i, 2);
            c.values[i] = half_to_float(h);
          } else if (stored == "uint16") {
            std::uint16_t h;
            std::memcpy(&h, p + 2 * i, 2);
            c.values[i] = static_cast<float>(h) * scale + min;
          } else if (stored == "uint8") {
            c.values[i] = static_cast<float>(static_cast<unsigned char>(p[i])) * scale + min;
          } else if (stored == "int32") {
            std::int32_t v;
            std::memcpy(&v, p + 4 * i, 4);
            c.values[i] = static_cast<float>(v);
          } else if (stored == "float32") {
            std::memcpy(&c.values[i], p + 4 * i, 4);
          } else {
            throw ModelError("model " + path_.string() + ": weight " + w.value("name", "") +
                             " has dtype " + stored +
                             "; expected float32, float16, int32 or "
                             "uint8/uint16 quantisation");
          }
        }
        offset += count * width;
        weights_[w.value("name", "")] = std::move(c);
      }
      if (offset != data.size()) {
        throw ModelError("model weights of " + path_.string() + ": " + std::to_string(data.size()) +
                         " bytes, the manifest describes " + std::to_string(offset) +
                         ": run scripts/setup again");
      }
    }
  }

  const Constant& constant(const std::string& input, const std::string& user) {
    const Value& v = resolve(input);
    if (!v.constant) fail(user, "needs " + input + " to be a constant");
    return v.c;
  }

  int add(const std::string& name, const std::string& type, cv::dnn::LayerParams& p,
          std::initializer_list<Tensor> inputs) {
    p.name = name;
    p.type = type;
    const int id = out_.net.addLayer(name, type, p);
    int port = 0;
    for (const Tensor& in : inputs) out_.net.connect(in.layer, in.port, id, port++);
    return id;
  }

  // A tensor with its pending pad turned into a Padding layer.
  Tensor materialize(const Tensor& t, const std::string& name) {
    if (!t.padded) return t;
    cv::dnn::LayerParams p;
    p.set("paddings", cv::dnn::DictValue::arrayInt(t.pads.data(), 8));
    p.set("value", static_cast<double>(t.pad_value));
    Tensor out = t;
    out.layer = add(name + "/pad", "Padding", p, {Tensor{t.layer, t.port}});
    out.port = 0;
    out.padded = false;
    out.channels = t.channels + t.pads[2] + t.pads[3];
    out.pads = {};
    return out;
  }

  // The graph's axis (negative counts from the end) in memory's NCHW order.
  static int nchw_axis(int axis, bool nhwc) {
    if (axis < 0) axis += 4;
    if (!nhwc) return axis;
    static constexpr int kMap[] = {0, 2, 3, 1};  // NHWC index -> NCHW index
    return kMap[axis];
  }

  const Value& resolve(const std::string& input) {
    const std::string key = base_name(input) + ":" + std::to_string(port_of(input));
    if (auto it = values_.find(key); it != values_.end()) return it->second;
    if (!visiting_.insert(key).second) fail(base_name(input), "is part of a cycle");
    Value v = evaluate(base_name(input), port_of(input));
    visiting_.erase(key);
    return values_[key] = std::move(v);
  }

  Value evaluate(const std::string& name, int port) {
    const json& n = node_of(name);
    const std::string op = n["op"];
    const json inputs = n.value("input", json::array());
    const json attr = n.value("attr", json::object());
    auto in = [&](std::size_t i) -> std::string {
      if (i >= inputs.size()) fail(name, "(" + op + ") has too few inputs");
      return inputs[i];
    };
    Value v;
    if (op == "Const") {
      auto it = weights_.find(name);
      if (it == weights_.end()) fail(name, "is a constant missing from the weights manifest");
      v.constant = true;
      v.c = it->second;
      return v;
    }
    if (op == "Placeholder") {
      // The network's one input, [1, C, H, W] as the graph declares it.
      if (++placeholders_ > 1) fail(name, "is a second input; one is supported");
      const auto& dims = attr["shape"]["shape"]["dim"];
      if (dims.size() != 4) fail(name, "is not a 4-d input");
      out_.net.setInputsNames({name});
      v.t.layer = 0;
      v.t.channels = std::stoi(dims[1]["size"].get<std::string>());
      return v;
    }
    if (op == "Identity") return resolve(in(0));
    if (op == "Transpose") {
      v = resolve(in(0));
      const Constant& perm = constant(in(1), name);
      const std::vector<float> to_nhwc{0, 2, 3, 1}, to_nchw{0, 3, 1, 2};
      if (v.constant) fail(name, "transposes a constant (not supported)");
      if (perm.values == to_nhwc && !v.t.nhwc) {
        v.t.nhwc = true;
      } else if (perm.values == to_nchw && v.t.nhwc) {
        v.t.nhwc = false;
      } else {
        fail(name, "has a transpose other than NCHW <-> NHWC of a 4-d tensor");
      }
      return v;
    }
    if (op == "Pad" || op == "PadV2") {
      v = resolve(in(0));
      if (v.constant) fail(name, "pads a constant (not supported)");
      const Constant& pads = constant(in(1), name);
      if (pads.shape != std::vector<int>{4, 2}) fail(name, "paddings are not 4x2");
      float value = 0;
      if (op == "PadV2") value = constant(in(2), name).values.at(0);
      if (v.t.padded && value != v.t.pad_value) v.t = materialize(v.t, name + "/before");
      for (int axis = 0; axis < 4; ++axis) {
        const int a = nchw_axis(axis, v.t.nhwc);
        v.t.pads[static_cast<std::size_t>(2 * a)] += static_cast<int>(pads.values[2 * axis]);
        v.t.pads[static_cast<std::size_t>(2 * a + 1)] +=
            static_cast<int>(pads.values[2 * axis + 1]);
      }
      v.t.padded = true;
      v.t.pad_value = value;
      return v;
    }
    if (op == "Conv2D") return conv(name, n, in(0), in(1));
    if (op == "MaxPool") return max_pool(name, attr, in(0));
    if (op == "LeakyRelu" || op == "Relu" || op == "Sigmoid") {
      v = resolve(in(0));
      if (v.constant) fail(name, "applies " + op + " to a constant (not supported)");
      v.t = materialize(v.t, name);
      cv::dnn::LayerParams p;
      if (op == "LeakyRelu") p.set("negative_slope", attr["alpha"].value("f", 0.2));
      v.t.layer = add(name, op == "Sigmoid" ? "Sigmoid" : "ReLU", p, {v.t});
      v.t.port = 0;
      return v;
    }
    if (op == "Add" || op == "AddV2") {
      const Value& a = resolve(in(0));
      const Value& b = resolve(in(1));
      // A convolution's bias, taken by the convolution when it was made (see conv()).
      if (auto it = bias_of_.find(name); it != bias_of_.end()) return resolve(it->second);
      if (a.constant || b.constant) fail(name, "adds a constant that is not a convolution bias");
      Tensor ta = materialize(a.t, name + "/a"), tb = materialize(b.t, name + "/b");
      if (ta.nhwc != tb.nhwc) fail(name, "adds an NHWC and an NCHW tensor");
      cv::dnn::LayerParams p;
      p.set("operation", "sum");
      v.t = ta;
      v.t.layer = add(name, "Eltwise", p, {ta, tb});
      v.t.port = 0;
      return v;
    }
    if (op == "ConcatV2") {
      const std::size_t count = inputs.size() - 1;
      const int axis = static_cast<int>(constant(in(count), name).values.at(0));
      std::vector<Tensor> parts;
      for (std::size_t i = 0; i < count; ++i) {
        const Value& part = resolve(in(i));
        if (part.constant) fail(name, "concatenates a constant (not supported)");
        parts.push_back(materialize(part.t, name + "/" + std::to_string(i)));
        if (parts.back().nhwc != parts.front().nhwc) fail(name, "mixes NHWC and NCHW inputs");
      }
      cv::dnn::LayerParams p;
      p.set("axis", nchw_axis(axis, parts.front().nhwc));
      p.name = name;
      p.type = "Concat";
      const int id = out_.net.addLayer(name, "Concat", p);
      v.t = parts.front();
      v.t.channels = 0;
      for (std::size_t i = 0; i < parts.size(); ++i) {
        out_.net.connect(parts[i].layer, parts[i].port, id, static_cast<int>(i));
        v.t.channels += parts[i].channels;
      }
      if (nchw_axis(axis, v.t.nhwc) != 1) v.t.channels = parts.front().channels;
      v.t.layer = id;
      v.t.port = 0;
      return v;
    }
    if (op == "ResizeBilinear") {
      v = resolve(in(0));
      if (v.constant || !v.t.nhwc) fail(name, "resizes something that is not an NHWC tensor");
      v.t = materialize(v.t, name);
      const Constant& size = constant(in(1), name);
      cv::dnn::LayerParams p;
      p.set("interpolation", "bilinear");
      p.set("height", static_cast<int>(size.values.at(0)));
      p.set("width", static_cast<int>(size.values.at(1)));
      p.set("align_corners",
            attr.contains("align_corners") && attr["align_corners"].value("b", false));
      p.set("half_pixel_centers",
            attr.contains("half_pixel_centers") && attr["half_pixel_centers"].value("b", false));
      v.t.layer = add(name, "Resize", p, {v.t});
      v.t.port = 0;
      return v;
    }
    if (op == "SplitV") {
      // All outputs come from one Slice layer, made once and shared.
      const std::string key = name + "#slice";
      if (!values_.count(key)) {
        Value src = resolve(in(0));
        if (src.constant) fail(name, "splits a constant (not supported)");
        src.t = materialize(src.t, name);
        const Constant& sizes = constant(in(1), name);
        const int axis =
            nchw_axis(static_cast<int>(constant(in(2), name).values.at(0)), src.t.nhwc);
        std::vector<int> points;
        int at = 0;
        for (std::size_t i = 0; i + 1 < sizes.values.size(); ++i) {
          at += static_cast<int>(sizes.values[i]);
          points.push_back(at);
        }
        cv::dnn::LayerParams p;
        p.set("axis", axis);
        p.set("slice_point",
              cv::dnn::DictValue::arrayInt(points.data(), static_cast<int>(points.size())));
        Value slice = src;
        slice.t.layer = add(name, "Slice", p, {src.t});
        slice.c.values = sizes.values;  // split sizes, for the channel count below
        slice.c.shape = {axis};
        values_[key] = slice;
      }
      const Value& slice = values_[key];
      v = slice;
      v.c = {};
      v.t.port = port;
      if (slice.c.shape.at(0) == 1) {
        v.t.channels = static_cast<int>(slice.c.values.at(static_cast<std::size_t>(port)));
      }
      return v;
    }
    fail(name, "has operator " + op + ", which this loader does not know");
  }

  Value conv(const std::string& name, const json& n, const std::string& input,
             const std::string& filter_name) {
    const json attr = n.value("attr", json::object());
    Value v = resolve(input);
    if (v.constant || !v.t.nhwc) fail(name, "convolves something that is not an NHWC tensor");
    const Constant& filter = constant(filter_name, name);  // HWIO
    if (filter.shape.size() != 4) fail(name, "has a filter of shape " + shape_text(filter.shape));
    const int kh = filter.shape[0], kw = filter.shape[1], ci = filter.shape[2],
              co = filter.shape[3];
    auto ints = [&](const char* key) {
      std::vector<int> out;
      if (attr.contains(key)) {
        for (const auto& i : attr[key]["list"].value("i", json::array())) {
          out.push_back(std::stoi(i.get<std::string>()));
        }
      }
      return out;
    };
    const std::vector<int> strides = ints("strides"), dilations = ints("dilations");
    const std::string padding = attr.contains("padding") ? attr["padding"].value("s", "") : "";
    if (padding != "VkFMSUQ=") fail(name, "has padding other than VALID");  // base64 "VALID"
    Tensor t = v.t;
    std::array<int, 4> pad{};  // t, l, b, r
    if (t.padded && t.pad_value == 0 && t.pads[0] == 0 && t.pads[1] == 0 && t.pads[2] == 0 &&
        t.pads[3] == 0) {
      pad = {t.pads[4], t.pads[6], t.pads[5], t.pads[7]};
      t.padded = false;
      t.pads = {};
    }
    t = materialize(t, name);
    if (t.channels <= 0 || t.channels % ci != 0) {
      fail(name, "has a filter for " + std::to_string(ci) + " input channels, the input has " +
                     std::to_string(t.channels));
    }
    // OIHW weights; the bias of the Add right after (if that is all it is) goes in too.
    cv::dnn::LayerParams p;
    const int shape[] = {co, ci, kh, kw};
    cv::Mat w(4, shape, CV_32F);
    float* wp = w.ptr<float>();
    for (int o = 0; o < co; ++o)
      for (int i = 0; i < ci; ++i)
        for (int y = 0; y < kh; ++y)
          for (int x = 0; x < kw; ++x)
            wp[((o * ci + i) * kh + y) * kw + x] =
                filter.values[static_cast<std::size_t>(((y * kw + x) * ci + i) * co + o)];
    p.blobs.push_back(w);
    out_.weight_bytes += w.total() * sizeof(float);
    bool bias = false;
    if (auto it = consumers_.find(name); it != consumers_.end() && it->second.size() == 1) {
      const json& next = node_of(it->second[0]);
      const std::string op = next["op"];
      if ((op == "Add" || op == "AddV2") && next["input"].size() == 2) {
        const std::string other =
            base_name(next["input"][0]) == name ? next["input"][1] : next["input"][0];
        if (node_of(base_name(other))["op"] == "Const") {
          const Constant& b = constant(other, name);
          if (b.values.size() == static_cast<std::size_t>(co) &&
              (b.shape.size() == 1 || b.shape == std::vector<int>{1, 1, 1, co})) {
            p.blobs.push_back(cv::Mat(1, co, CV_32F, const_cast<float*>(b.values.data())).clone());
            out_.weight_bytes += static_cast<std::size_t>(co) * sizeof(float);
            bias = true;
            bias_of_[it->second[0]] = name;
          }
        }
      }
    }
    p.set("kernel_h", kh);
    p.set("kernel_w", kw);
    p.set("stride_h", strides.size() == 4 ? strides[1] : 1);
    p.set("stride_w", strides.size() == 4 ? strides[2] : 1);
    p.set("dilation_h", dilations.size() == 4 ? dilations[1] : 1);
    p.set("dilation_w", dilations.size() == 4 ? dilations[2] : 1);
    p.set("pad_t", pad[0]);
    p.set("pad_l", pad[1]);
    p.set("pad_b", pad[2]);
    p.set("pad_r", pad[3]);
    p.set("num_output", co);
    p.set("group", t.channels / ci);
    p.set("bias_term", bias);
    Value out;
    out.t = t;
    out.t.layer = add(name, "Convolution", p, {t});
    out.t.port = 0;
    out.t.channels = co;
    return out;
  }

  Value max_pool(const std::string& name, const json& attr, const std::string& input) {
    Value v = resolve(input);
    if (v.constant || !v.t.nhwc) fail(name, "pools something that is not an NHWC tensor");
    auto ints = [&](const char* key) {
      std::vector<int> out;
      for (const auto& i : attr[key]["list"].value("i", json::array())) {
        out.push_back(std::stoi(i.get<std::string>()));
      }
      return out;
    };
    const std::vector<int> k = ints("ksize"), s = ints("strides");
    if (k.size() != 4 || s.size() != 4) fail(name, "has no 4-d ksize/strides");
    const std::string padding = attr["padding"].value("s", "");
    if (padding != "VkFMSUQ=") fail(name, "has padding other than VALID");
    Tensor t = materialize(v.t, name);
    cv::dnn::LayerParams p;
    p.set("pool", "max");
    p.set("kernel_h", k[1]);
    p.set("kernel_w", k[2]);
    p.set("stride_h", s[1]);
    p.set("stride_w", s[2]);
    p.set("pad", 0);
    p.set("ceil_mode", false);
    v.t = t;
    v.t.layer = add(name, "Pooling", p, {t});
    v.t.port = 0;
    return v;
  }

  const std::filesystem::path& path_;
  TfjsNet& out_;
  std::map<std::string, json> nodes_;
  std::map<std::string, std::vector<std::string>> consumers_;
  std::map<std::string, Constant> weights_;
  std::map<std::string, Value> values_;
  std::map<std::string, std::string> bias_of_;  // Add node -> the convolution that took it
  std::set<std::string> visiting_;
  int placeholders_ = 0;
};

}  // namespace

TfjsNet load_tfjs_graph(const std::filesystem::path& model_json,
                        const std::vector<std::string>& outputs) {
  TfjsNet net;
  GraphBuilder builder(model_json, net);
  builder.build(outputs);
  net.net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  return net;
}

}  // namespace marvin::vision
