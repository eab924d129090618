// The serial link to the body's MCU (firmware/PROTOCOL.md), over Boost.Asio serial_port.
//
// A SerialLink owns one I/O thread. It opens the tty (a real UART or marvin-mcu-sim's
// pseudo-terminal), encodes commands, decodes telemetry, and keeps trying to reopen the
// device whenever it disappears (read/write error, end of file, open failure) or falls
// silent; each loss is reported (log, state callback, counters). Thread-safe: every method
// may be called from any thread. Callbacks run on the link's I/O thread and must not block.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <variant>

#include "protocol/marvin_protocol.h"

namespace boost::asio {
class io_context;
}

namespace marvin::devices {

struct LinkOptions {
  std::string path;                                   // tty to open, e.g. /dev/ttyACM0
  std::chrono::milliseconds reconnect_interval{200};  // between attempts to reopen
  // No valid frame this long: reopen. Not counted: a wait the host itself slept through (a
  // stalled process), when the telemetry is there to be read.
  std::chrono::milliseconds silence_timeout{1500};
};

// Telemetry from the MCU, decoded. mcu_time_ms is the MCU's clock (28 bits, wraps after
// about 74 hours); host_time_ms the host's steady clock when the frame arrived.
struct SonarReading {
  int angle_deg;
  int distance_mm;  // capped at 2500
  bool echo;        // false: nothing within 2.5 m
  std::uint32_t mcu_time_ms;
  std::int64_t host_time_ms;
};
struct Ack {
  int type;  // the acknowledged frame type (MV_LOCOMOTION, MV_HEAD_TILT, ...)
  int arg;
};
struct Fault {
  int code;   // mv_fault_code
  int value;  // deadman: the timeout in ms; obstacle: horizontal distance in mm
  std::uint32_t mcu_time_ms;
};
struct Status {
  int left_speed, right_speed;  // 0..255
  bool left_backward, right_backward;
  int head_deg;
  bool sweeping, blocked;
  int rx_errors;
  std::uint32_t mcu_time_ms;
};
using Telemetry = std::variant<SonarReading, Ack, Fault, Status>;

// Decodes one telemetry frame into *out; false if the frame is not telemetry.
bool decode_telemetry(const mv_frame& frame, std::int64_t host_time_ms, Telemetry* out);

enum class LinkState { kDisconnected, kConnected };

class SerialLink {
 public:
  struct Counters {
    std::uint64_t connects = 0, losses = 0;
    std::uint64_t frames_sent = 0, frames_received = 0, bytes_rejected = 0;
  };
  using TelemetryCallback = std::function<void(const Telemetry&)>;
  using StateCallback = std::function<void(LinkState state, const std::string& why)>;

  // Starts the I/O thread and the first attempt to open options.path (failures are retried,
  // never thrown).
  explicit SerialLink(LinkOptions options);
  // Stops the thread and closes the device.
  ~SerialLink();
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;

  // Queues one frame (plus END) for sending. Returns false, dropping it, when the link is
  // down or the frame cannot be encoded (an argument out of range).
  bool send(const mv_frame& frame);
  bool send_locomotion(std::uint8_t direction, std::uint8_t speed);
  bool send_ext(std::uint8_t type, std::initializer_list<std::uint8_t> payload);

  // Adds a callback for every telemetry frame / state change; returns an id for remove.
  int add_telemetry_callback(TelemetryCallback callback);
  int add_state_callback(StateCallback callback);
  void remove_callback(int id);

  LinkState state() const;
  Counters counters() const;
  // The link's I/O context (for devices' timers); its thread runs until destruction.
  boost::asio::io_context& io_context();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// Host steady clock in ms (the clock of host_time_ms and ScanPoint::time_ms).
std::int64_t steady_ms();

}  // namespace marvin::devices
