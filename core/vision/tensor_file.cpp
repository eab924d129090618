#include "vision/tensor_file.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "vision/model_files.h"

namespace marvin::vision {
namespace {

constexpr char kMagic[8] = {'M', 'V', 'T', 'E', 'N', 'S', 'O', 'R'};

class Reader {
 public:
  Reader(const std::filesystem::path& path, std::string bytes)
      : path_(path), bytes_(std::move(bytes)) {}
  uint32_t u32(const std::string& what) {
    uint32_t v = 0;
    take(&v, 4, what);
    return v;
  }
  void take(void* out, std::size_t n, const std::string& what) {
    if (bytes_.size() - pos_ < n) {
      throw ModelError("model " + path_.string() + ": truncated at byte " + std::to_string(pos_) +
                       " while reading " + what + " (file has " + std::to_string(bytes_.size()) +
                       " bytes): run scripts/setup again");
    }
    std::memcpy(out, bytes_.data() + pos_, n);
    pos_ += n;
  }
  std::size_t pos() const { return pos_; }
  std::size_t size() const { return bytes_.size(); }

 private:
  const std::filesystem::path& path_;
  std::string bytes_;
  std::size_t pos_ = 0;
};

}  // namespace

TensorMap read_tensor_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ModelError("model " + path.string() +
                     ": cannot open (missing?): run scripts/setup, then build, to fetch and convert "
                     "the models");
  }
  Reader r(path, std::string(std::istreambuf_iterator<char>(in), {}));
  char magic[8];
  r.take(magic, 8, "the file header");
  if (std::memcmp(magic, kMagic, 8) != 0) {
    throw ModelError("model " + path.string() +
                     ": not a Marvin tensor file (expected \"MVTENSOR\" at byte 0)");
  }
  const uint32_t version = r.u32("the version");
  if (version != 1) {
    throw ModelError("model " + path.string() + ": tensor file version " +
                     std::to_string(version) + ", expected 1");
  }
  const uint32_t count = r.u32("the tensor count");
  TensorMap out;
  for (uint32_t i = 0; i < count; ++i) {
    const std::string which = "tensor " + std::to_string(i);
    const uint32_t name_len = r.u32(which + "'s name length");
    if (name_len > 256) {
      throw ModelError("model " + path.string() + ": " + which + " has a name of " +
                       std::to_string(name_len) + " bytes at byte " + std::to_string(r.pos() - 4) +
                       " (expected at most 256)");
    }
    std::string name(name_len, '\0');
    r.take(name.data(), name_len, which + "'s name");
    const uint32_t rank = r.u32(name + "'s rank");
    if (rank > 8) {
      throw ModelError("model " + path.string() + ": tensor " + name + " has rank " +
                       std::to_string(rank) + " (expected at most 8)");
    }
    Tensor t;
    std::size_t n = 1;
    for (uint32_t d = 0; d < rank; ++d) {
      const uint32_t dim = r.u32(name + "'s shape");
      if (dim == 0 || dim > (1u << 24)) {
        throw ModelError("model " + path.string() + ": tensor " + name + " has dimension " +
                         std::to_string(dim) + " (expected 1 .. 16777216)");
      }
      t.shape.push_back(static_cast<int>(dim));
      n *= dim;
    }
    t.values.resize(n);
    r.take(t.values.data(), n * sizeof(float), name + "'s values");
    out.emplace(std::move(name), std::move(t));
  }
  if (r.pos() != r.size()) {
    throw ModelError("model " + path.string() + ": " + std::to_string(r.size() - r.pos()) +
                     " unexpected bytes after the last tensor at byte " + std::to_string(r.pos()));
  }
  return out;
}

void write_tensor_file(const std::filesystem::path& path, const TensorMap& tensors) {
  const auto tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    auto u32 = [&](uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
    out.write(kMagic, 8);
    u32(1);
    u32(static_cast<uint32_t>(tensors.size()));
    for (const auto& [name, t] : tensors) {
      u32(static_cast<uint32_t>(name.size()));
      out.write(name.data(), static_cast<std::streamsize>(name.size()));
      u32(static_cast<uint32_t>(t.shape.size()));
      for (int d : t.shape) u32(static_cast<uint32_t>(d));
      out.write(reinterpret_cast<const char*>(t.values.data()),
                static_cast<std::streamsize>(t.values.size() * sizeof(float)));
    }
    if (!out.flush()) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace marvin::vision
