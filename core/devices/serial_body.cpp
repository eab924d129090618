// The serial body. See serial_body.h.
#include "devices/serial_body.h"

#include "common/log.h"

namespace marvin::devices {

SerialBody::SerialBody(const std::string& tty_path) : SerialBody(LinkOptions{tty_path}) {}

SerialBody::SerialBody(LinkOptions options, SweepSettings sweep)
    : link_(std::move(options)), motors_(link_), head_(link_), sonar_(link_), light_(link_) {
  sonar_.sweep(sweep);  // dropped if not connected yet; sent again on connect
  auto resend_all = [this] {
    head_.resend();
    light_.resend();
    sonar_.resend();
  };
  state_callback_ =
      link_.add_state_callback([this, resend_all](LinkState state, const std::string&) {
        if (state == LinkState::kConnected) {
          resend_all();
        } else {
          motors_.forget();  // the MCU's deadman stops the wheels
        }
        // The link's state is already updated: taking the lock orders this notification
        // after a waiter's check of it.
        { std::lock_guard lock(connected_mutex_); }
        connected_changed_.notify_all();
      });
  telemetry_callback_ = link_.add_telemetry_callback([this](const Telemetry& t) {
    if (auto* f = std::get_if<Fault>(&t)) {
      if (f->code == MV_FAULT_DEADMAN) motors_.forget();
      if (f->code == MV_FAULT_OBSTACLE) {
        motors_.stopped_by_mcu();
        log(LogLevel::kInfo, "devices",
            "obstacle ahead at " + std::to_string(f->value) + " mm: stopped");
      }
    }
  });
  // Connected before the callback was registered: send now (a second copy is harmless).
  if (link_.state() == LinkState::kConnected) resend_all();
}

SerialBody::~SerialBody() {
  link_.remove_callback(telemetry_callback_);
  link_.remove_callback(state_callback_);
}

bool SerialBody::wait_connected(std::chrono::milliseconds timeout) {
  std::unique_lock lock(connected_mutex_);
  return connected_changed_.wait_for(lock, timeout,
                                     [this] { return link_.state() == LinkState::kConnected; });
}

void SerialBody::move(Direction direction, std::uint8_t speed, std::chrono::milliseconds duration) {
  // Turning on the spot: what the sonar saw so far is in another direction (sonar_scanner.h).
  if (direction == Direction::kLeft || direction == Direction::kRight) sonar_.forget_readings();
  motors_.drive(direction, speed, duration);
}
void SerialBody::stop() { motors_.stop(); }
void SerialBody::tilt_head(int degrees) { head_.tilt(degrees); }
std::vector<ScanPoint> SerialBody::latest_scan() { return sonar_.latest_scan(); }
void SerialBody::set_light(Light light) { light_.set(light); }

}  // namespace marvin::devices
