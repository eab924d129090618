#include "perception/kws/onnx_file.h"

#include <cstring>
#include <fstream>
#include <iterator>

namespace marvin::perception::kws {
namespace {

// One length-delimited protobuf message: [begin, end) of the file's bytes.
class WireReader {
 public:
  WireReader(const std::string& bytes, std::size_t begin, std::size_t end, const std::string& file,
             const char* what)
      : bytes_(bytes), pos_(begin), end_(end), file_(file), what_(what) {}

  bool done() const { return pos_ >= end_; }
  std::size_t pos() const { return pos_; }

  std::uint64_t varint() {
    std::uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos_ >= end_) fail("a varint runs past the end");
      const auto byte = static_cast<std::uint8_t>(bytes_[pos_++]);
      value |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
      if ((byte & 0x80) == 0) return value;
    }
    fail("a varint is longer than 10 bytes");
  }

  // Reads a field key; returns false at the end of the message.
  bool next(std::uint32_t& field, std::uint32_t& wire_type) {
    if (done()) return false;
    const std::uint64_t key = varint();
    field = static_cast<std::uint32_t>(key >> 3);
    wire_type = static_cast<std::uint32_t>(key & 7);
    return true;
  }

  // A length-delimited field's [begin, end).
  std::pair<std::size_t, std::size_t> span() {
    const std::uint64_t length = varint();
    if (length > end_ - pos_) fail("a field of " + std::to_string(length) + " bytes runs past the end");
    const std::size_t begin = pos_;
    pos_ += static_cast<std::size_t>(length);
    return {begin, pos_};
  }

  std::string string() {
    const auto [b, e] = span();
    return bytes_.substr(b, e - b);
  }

  float fixed32_float() {
    if (end_ - pos_ < 4) fail("a 4-byte field runs past the end");
    float value = 0.0f;
    std::memcpy(&value, bytes_.data() + pos_, 4);
    pos_ += 4;
    return value;
  }

  void skip(std::uint32_t wire_type) {
    switch (wire_type) {
      case 0: varint(); return;
      case 1: advance(8); return;
      case 2: span(); return;
      case 5: advance(4); return;
      default: fail("unknown wire type " + std::to_string(wire_type));
    }
  }

  WireReader sub(std::pair<std::size_t, std::size_t> range, const char* what) const {
    return WireReader(bytes_, range.first, range.second, file_, what);
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw OnnxError(file_ + ": " + what_ + " at byte " + std::to_string(pos_) + ": " + message);
  }

 private:
  void advance(std::size_t n) {
    if (end_ - pos_ < n) fail("a fixed-size field runs past the end");
    pos_ += n;
  }

  const std::string& bytes_;
  std::size_t pos_;
  std::size_t end_;
  const std::string& file_;
  const char* what_;
};

// Repeated int64 fields come packed (wire type 2) or one by one (wire type 0).
void read_ints(WireReader& r, std::uint32_t wire_type, std::vector<std::int64_t>& out) {
  if (wire_type == 0) {
    out.push_back(static_cast<std::int64_t>(r.varint()));
    return;
  }
  WireReader packed = r.sub(r.span(), "packed ints");
  while (!packed.done()) out.push_back(static_cast<std::int64_t>(packed.varint()));
}

void read_floats(WireReader& r, std::uint32_t wire_type, std::vector<float>& out) {
  if (wire_type == 5) {
    out.push_back(r.fixed32_float());
    return;
  }
  WireReader packed = r.sub(r.span(), "packed floats");
  while (!packed.done()) out.push_back(packed.fixed32_float());
}

constexpr std::int64_t kFloat = 1;
constexpr std::int64_t kInt32 = 6;
constexpr std::int64_t kInt64 = 7;

OnnxTensor read_tensor(WireReader r, std::string& name) {
  OnnxTensor t;
  std::int64_t data_type = 0;
  std::string raw;
  bool has_raw = false;
  std::uint32_t field = 0, wt = 0;
  while (r.next(field, wt)) {
    if (field == 1) read_ints(r, wt, t.dims);
    else if (field == 2) data_type = static_cast<std::int64_t>(r.varint());
    else if (field == 4) read_floats(r, wt, t.floats);
    else if (field == 5 || field == 7) read_ints(r, wt, t.ints);
    else if (field == 8) name = r.string();
    else if (field == 9) { raw = r.string(); has_raw = true; }
    else r.skip(wt);
  }
  const std::size_t count = t.size();
  if (has_raw) {
    const std::size_t width = data_type == kInt32 ? 4 : (data_type == kFloat ? 4 : 8);
    if (data_type != kFloat && data_type != kInt64 && data_type != kInt32) {
      r.fail("tensor '" + name + "' has data type " + std::to_string(data_type) +
             ", expected float32 (1), int32 (6) or int64 (7)");
    }
    if (raw.size() != count * width) {
      r.fail("tensor '" + name + "' holds " + std::to_string(raw.size()) + " bytes, expected " +
             std::to_string(count * width));
    }
    if (data_type == kFloat) {
      t.floats.resize(count);
      std::memcpy(t.floats.data(), raw.data(), raw.size());
    } else if (data_type == kInt64) {
      t.ints.resize(count);
      std::memcpy(t.ints.data(), raw.data(), raw.size());
    } else {
      t.ints.resize(count);
      for (std::size_t k = 0; k < count; ++k) {
        std::int32_t v = 0;
        std::memcpy(&v, raw.data() + 4 * k, 4);
        t.ints[k] = v;
      }
    }
  } else if (t.floats.size() + t.ints.size() != count &&
             (data_type == kFloat || data_type == kInt64 || data_type == kInt32)) {
    r.fail("tensor '" + name + "' holds " + std::to_string(t.floats.size() + t.ints.size()) +
           " values, its dims say " + std::to_string(count));
  }
  return t;
}

void read_attribute(WireReader r, OnnxNode& node) {
  std::string name;
  OnnxAttribute a;
  std::uint32_t field = 0, wt = 0;
  while (r.next(field, wt)) {
    if (field == 1) name = r.string();
    else if (field == 2) a.f = r.fixed32_float();
    else if (field == 3) a.i = static_cast<std::int64_t>(r.varint());
    else if (field == 4) a.s = r.string();
    else if (field == 5) { std::string tensor_name; a.t = read_tensor(r.sub(r.span(), "tensor attribute"), tensor_name); }
    else if (field == 7) read_floats(r, wt, a.floats);
    else if (field == 8) read_ints(r, wt, a.ints);
    else r.skip(wt);
  }
  node.attributes[name] = std::move(a);
}

OnnxNode read_node(WireReader r) {
  OnnxNode node;
  std::uint32_t field = 0, wt = 0;
  while (r.next(field, wt)) {
    if (field == 1) node.inputs.push_back(r.string());
    else if (field == 2) node.outputs.push_back(r.string());
    else if (field == 4) node.op_type = r.string();
    else if (field == 5) read_attribute(r.sub(r.span(), "attribute"), node);
    else r.skip(wt);
  }
  return node;
}

}  // namespace

std::size_t OnnxTensor::size() const {
  std::size_t n = 1;
  for (const std::int64_t d : dims) n *= static_cast<std::size_t>(d < 0 ? 0 : d);
  return n;
}

std::vector<std::int64_t> OnnxNode::ints(const std::string& name,
                                         std::vector<std::int64_t> fallback) const {
  const auto it = attributes.find(name);
  return it == attributes.end() ? fallback : it->second.ints;
}

const OnnxTensor& OnnxGraph::constant(const std::string& name) const {
  const auto it = constants.find(name);
  if (it == constants.end()) {
    throw OnnxError(file.string() + ": the graph has no constant tensor '" + name + "'");
  }
  return it->second;
}

OnnxGraph read_onnx(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw OnnxError(file.string() + ": cannot open the file");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string name = file.string();
  OnnxGraph graph;
  graph.file = file;
  WireReader model(bytes, 0, bytes.size(), name, "ModelProto");
  bool has_graph = false;
  std::uint32_t field = 0, wt = 0;
  while (model.next(field, wt)) {
    if (field != 7 || wt != 2) {
      model.skip(wt);
      continue;
    }
    has_graph = true;
    WireReader g = model.sub(model.span(), "GraphProto");
    while (g.next(field, wt)) {
      if (field == 1 && wt == 2) {
        graph.nodes.push_back(read_node(g.sub(g.span(), "NodeProto")));
        OnnxNode& node = graph.nodes.back();
        if (node.op_type == "Constant" && node.outputs.size() == 1) {
          const auto value = node.attributes.find("value");
          if (value != node.attributes.end()) graph.constants[node.outputs[0]] = value->second.t;
        }
      } else if (field == 5 && wt == 2) {
        std::string tensor_name;
        OnnxTensor t = read_tensor(g.sub(g.span(), "initializer"), tensor_name);
        graph.constants[tensor_name] = std::move(t);
      } else {
        g.skip(wt);
      }
    }
  }
  if (!has_graph || graph.nodes.empty()) {
    throw OnnxError(name + ": no graph with nodes in " + std::to_string(bytes.size()) +
                    " bytes (is it an ONNX model?)");
  }
  return graph;
}

}  // namespace marvin::perception::kws
