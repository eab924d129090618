#include "telephony/netstring.h"

#include <cctype>

namespace marvin::telephony {

std::string encode_netstring(std::string_view payload) {
  std::string out = std::to_string(payload.size());
  out += ':';
  out.append(payload);
  out += ',';
  return out;
}

void NetstringReader::drop(std::size_t count) {
  buffer_.erase(0, count);
  consumed_total_ += count;
}

std::optional<NetstringReader::Frame> NetstringReader::next() {
  if (buffer_.empty()) return std::nullopt;
  const std::size_t start = consumed_total_;
  std::size_t digits = 0;
  while (digits < buffer_.size() && std::isdigit(static_cast<unsigned char>(buffer_[digits]))) {
    ++digits;
  }
  auto fail = [&](std::size_t skip, const std::string& why) {
    drop(skip);
    return Frame{{}, "control socket: malformed netstring at byte " + std::to_string(start) +
                         ": " + why};
  };
  if (digits == 0) {
    // Skip to the next digit: the most likely start of a good frame.
    std::size_t skip = 1;
    while (skip < buffer_.size() && !std::isdigit(static_cast<unsigned char>(buffer_[skip]))) {
      ++skip;
    }
    return fail(skip, "expected a length (digits), got '" + buffer_.substr(0, 1) + "'");
  }
  if (digits > 6) return fail(digits, "length has more than 6 digits");
  if (digits == buffer_.size()) return std::nullopt;
  if (buffer_[digits] != ':') {
    return fail(digits, "expected ':' after the length " + buffer_.substr(0, digits));
  }
  const std::size_t size = std::stoul(buffer_.substr(0, digits));
  if (size > kMaxFrame) return fail(digits + 1, "length " + std::to_string(size) + " too long");
  const std::size_t total = digits + 1 + size + 1;
  if (buffer_.size() < total) return std::nullopt;
  if (buffer_[total - 1] != ',') {
    return fail(digits + 1, "expected ',' after " + std::to_string(size) + " bytes");
  }
  Frame frame{buffer_.substr(digits + 1, size), {}};
  drop(total);
  return frame;
}

}  // namespace marvin::telephony
