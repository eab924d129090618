// Netstring framing ("<length>:<bytes>,") as baresip's ctrl_tcp module speaks it.
//
// The reader takes bytes as they arrive from the socket and hands out whole frames. A
// malformed frame (a length that is not digits, too long, or a missing ',') is reported
// with what was expected and the byte offset; the reader then skips to the next byte that
// can start a frame, so one bad frame does not cost the connection.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace marvin::telephony {

// "<size>:<payload>,"
std::string encode_netstring(std::string_view payload);

class NetstringReader {
 public:
  // Frames longer than this are malformed (ctrl_tcp's events are a few hundred bytes).
  static constexpr std::size_t kMaxFrame = 64 * 1024;

  void feed(std::string_view bytes) { buffer_.append(bytes); }

  // One result of next(): a payload, or an error message about skipped bytes.
  struct Frame {
    std::string payload;
    std::string error;  // empty when `payload` is a good frame
  };
  // The next complete frame or error, nullopt when more bytes are needed.
  std::optional<Frame> next();

 private:
  std::string buffer_;
  std::size_t consumed_total_ = 0;  // bytes dropped so far, for error offsets
  void drop(std::size_t count);
};

}  // namespace marvin::telephony
