// The serial link to the MCU. See serial_link.h.
#include "devices/serial_link.h"

#include <array>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <deque>
#include <future>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "common/log.h"

namespace marvin::devices {

namespace asio = boost::asio;

std::int64_t steady_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

bool decode_telemetry(const mv_frame& f, std::int64_t host_time_ms, Telemetry* out) {
  switch (f.type) {
    case MV_SONAR_READING:
      *out = SonarReading{f.payload[0], mv_get14(&f.payload[2]), (f.payload[1] & 1u) == 0,
                          mv_get28(&f.payload[4]), host_time_ms};
      return true;
    case MV_ACK:
      *out = Ack{f.payload[0], f.payload[1]};
      return true;
    case MV_FAULT:
      *out = Fault{f.payload[0], mv_get14(&f.payload[1]), mv_get28(&f.payload[3])};
      return true;
    case MV_STATUS: {
      std::uint16_t left = mv_get14(&f.payload[0]), right = mv_get14(&f.payload[2]);
      Status s{};
      s.left_speed = left & 0xFF;
      s.left_backward = (left & 0x100) != 0;
      s.right_speed = right & 0xFF;
      s.right_backward = (right & 0x100) != 0;
      s.head_deg = static_cast<int>(f.payload[4]) - 64;
      s.sweeping = (f.payload[5] & MV_STATUS_SWEEPING) != 0;
      s.blocked = (f.payload[5] & MV_STATUS_BLOCKED) != 0;
      s.rx_errors = mv_get14(&f.payload[6]);
      s.mcu_time_ms = mv_get28(&f.payload[8]);
      *out = s;
      return true;
    }
    default:
      return false;
  }
}

class SerialLink::Impl {
 public:
  explicit Impl(LinkOptions options)
      : options_(std::move(options)),
        port_(io_),
        retry_(io_),
        watchdog_(io_),
        guard_(asio::make_work_guard(io_)) {
    mv_decoder_init(&decoder_);
    asio::post(io_, [this] {
      io_thread_id_.store(std::this_thread::get_id());
      try_open();
      arm_watchdog();
    });
    thread_ = std::thread([this] { io_.run(); });
  }

  ~Impl() {
    // Let queued frames (a last STOP_ALL) leave, for at most 500 ms.
    auto give_up = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
    while (std::chrono::steady_clock::now() < give_up) {
      auto empty = std::make_shared<std::promise<bool>>();
      auto f = empty->get_future();
      asio::post(io_, [this, empty] { empty->set_value(queue_.empty()); });
      if (f.wait_until(give_up) != std::future_status::ready || f.get()) break;
    }
    io_.stop();
    thread_.join();
    boost::system::error_code ec;
    port_.close(ec);
  }

  bool send(const mv_frame& frame) {
    std::vector<std::uint8_t> bytes(MV_MAX_FRAME + 1);
    std::size_t n = mv_encode_frame(&frame, bytes.data());
    if (n == 0 || state_.load() != LinkState::kConnected) return false;
    bytes[n] = MV_END;
    bytes.resize(n + 1);
    asio::post(io_, [this, b = std::move(bytes)]() mutable {
      if (!port_.is_open()) return;
      queue_.push_back(std::move(b));
      if (queue_.size() == 1) write_next();
    });
    std::lock_guard lock(mu_);
    counters_.frames_sent++;
    return true;
  }

  int add_callback(TelemetryCallback t, StateCallback s) {
    std::lock_guard lock(mu_);
    auto next = std::make_shared<Callbacks>(*callbacks_);
    int id = ++last_id_;
    (*next)[id] = {std::move(t), std::move(s)};
    callbacks_ = std::move(next);
    return id;
  }

  void remove_callback(int id) {
    {
      std::lock_guard lock(mu_);
      auto next = std::make_shared<Callbacks>(*callbacks_);
      next->erase(id);
      callbacks_ = std::move(next);
    }
    // Wait for a dispatch in progress on the I/O thread, so the callback's owner may go.
    if (std::this_thread::get_id() != io_thread_id_.load() && !io_.stopped()) {
      auto done = std::make_shared<std::promise<void>>();
      auto f = done->get_future();
      asio::post(io_, [done] { done->set_value(); });
      f.wait_for(std::chrono::seconds(5));
    }
  }

  LinkState state() const { return state_.load(); }
  Counters counters() const {
    std::lock_guard lock(mu_);
    return counters_;
  }
  asio::io_context& io() { return io_; }

 private:
  struct Entry {
    TelemetryCallback telemetry;
    StateCallback state;
  };
  using Callbacks = std::map<int, Entry>;

  std::shared_ptr<const Callbacks> snapshot() {
    std::lock_guard lock(mu_);
    return callbacks_;
  }

  void set_state(LinkState s, const std::string& why) {
    state_.store(s);
    auto callbacks = snapshot();  // keep the map alive while iterating
    for (auto& [id, e] : *callbacks)
      if (e.state) e.state(s, why);
  }

  void try_open() {
    boost::system::error_code ec;
    port_.open(options_.path, ec);
    if (!ec) {
      using sp = asio::serial_port_base;
      // Settings a pseudo-terminal may refuse are not fatal; a UART accepts them all.
      boost::system::error_code ignored;
      port_.set_option(sp::baud_rate(MV_BAUD_RATE), ignored);
      port_.set_option(sp::character_size(8), ignored);
      port_.set_option(sp::parity(sp::parity::none), ignored);
      port_.set_option(sp::stop_bits(sp::stop_bits::one), ignored);
      port_.set_option(sp::flow_control(sp::flow_control::none), ignored);
    }
    if (ec) {
      if (!open_failure_logged_) {
        log(LogLevel::kInfo, "devices",
            "serial link: cannot open " + options_.path + " (" + ec.message() + "), retrying");
        open_failure_logged_ = true;
      }
      retry_.expires_after(options_.reconnect_interval);
      retry_.async_wait([this](boost::system::error_code e) {
        if (!e) try_open();
      });
      return;
    }
    open_failure_logged_ = false;
    mv_decoder_init(&decoder_);
    last_rx_ms_ = steady_ms();
    {
      std::lock_guard lock(mu_);
      counters_.connects++;
    }
    log(LogLevel::kInfo, "devices", "serial link: connected to " + options_.path);
    set_state(LinkState::kConnected, "opened " + options_.path);
    read_next();
  }

  void lose(const std::string& why) {
    if (!port_.is_open()) return;
    boost::system::error_code ignored;
    port_.close(ignored);
    queue_.clear();
    {
      std::lock_guard lock(mu_);
      counters_.losses++;
    }
    log(LogLevel::kWarning, "devices", "serial link to " + options_.path + " lost: " + why);
    set_state(LinkState::kDisconnected, why);
    retry_.expires_after(options_.reconnect_interval);
    retry_.async_wait([this](boost::system::error_code e) {
      if (!e) try_open();
    });
  }

  void read_next() {
    port_.async_read_some(asio::buffer(rx_), [this](boost::system::error_code ec, std::size_t n) {
      if (ec) {
        if (ec != asio::error::operation_aborted) lose("read: " + ec.message());
        return;
      }
      received(n);
      read_next();
    });
  }

  void received(std::size_t n) {
    std::int64_t now = steady_ms();
    auto callbacks = snapshot();
    std::uint32_t rejected_before = decoder_.rejected;
    std::uint64_t frames = 0;
    for (std::size_t i = 0; i < n; ++i) {
      mv_frame f;
      if (!mv_decoder_push(&decoder_, rx_[i], &f)) continue;
      Telemetry t;
      if (!decode_telemetry(f, now, &t)) continue;
      ++frames;
      last_rx_ms_ = now;
      for (auto& [id, e] : *callbacks)
        if (e.telemetry) e.telemetry(t);
    }
    std::lock_guard lock(mu_);
    counters_.frames_received += frames;
    counters_.bytes_rejected += decoder_.rejected - rejected_before;
  }

  void write_next() {
    asio::async_write(port_, asio::buffer(queue_.front()),
                      [this](boost::system::error_code ec, std::size_t) {
                        if (ec) {
                          if (ec != asio::error::operation_aborted) lose("write: " + ec.message());
                          return;
                        }
                        if (!queue_.empty()) queue_.pop_front();
                        if (!queue_.empty()) write_next();
                      });
  }

  void arm_watchdog() {
    constexpr std::int64_t kPeriodMs = 100;
    const std::int64_t armed_ms = steady_ms();
    watchdog_.expires_after(std::chrono::milliseconds(kPeriodMs));
    watchdog_.async_wait([this, armed_ms](boost::system::error_code ec) {
      if (ec) return;
      // A watchdog that ran far too late means this process was not running (a stalled or
      // suspended host), so the silence was ours: the telemetry is waiting to be read. The
      // next round judges, after the reads queued with this one have run.
      const std::int64_t now = steady_ms();
      const bool on_time = now - armed_ms < 3 * kPeriodMs;
      if (on_time && port_.is_open() && now - last_rx_ms_ >= options_.silence_timeout.count())
        lose("no telemetry for " + std::to_string(options_.silence_timeout.count()) + " ms");
      arm_watchdog();
    });
  }

  LinkOptions options_;
  asio::io_context io_;
  asio::serial_port port_;
  asio::steady_timer retry_, watchdog_;
  asio::executor_work_guard<asio::io_context::executor_type> guard_;
  std::thread thread_;
  std::atomic<std::thread::id> io_thread_id_{};
  std::atomic<LinkState> state_{LinkState::kDisconnected};
  // I/O thread only:
  mv_decoder decoder_;
  std::array<std::uint8_t, 256> rx_{};
  std::deque<std::vector<std::uint8_t>> queue_;
  std::int64_t last_rx_ms_ = 0;
  bool open_failure_logged_ = false;
  // Guarded by mu_:
  mutable std::mutex mu_;
  Counters counters_;
  std::shared_ptr<const Callbacks> callbacks_ = std::make_shared<Callbacks>();
  int last_id_ = 0;
};

SerialLink::SerialLink(LinkOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
SerialLink::~SerialLink() = default;

bool SerialLink::send(const mv_frame& frame) { return impl_->send(frame); }

bool SerialLink::send_locomotion(std::uint8_t direction, std::uint8_t speed) {
  mv_frame f{};
  f.type = MV_LOCOMOTION;
  f.len = 2;
  f.payload[0] = direction;
  f.payload[1] = speed;
  return send(f);
}

bool SerialLink::send_ext(std::uint8_t type, std::initializer_list<std::uint8_t> payload) {
  mv_frame f{};
  if (payload.size() > MV_MAX_PAYLOAD) return false;
  f.type = type;
  f.len = static_cast<std::uint8_t>(payload.size());
  std::size_t i = 0;
  for (std::uint8_t b : payload) f.payload[i++] = b;
  return send(f);
}

int SerialLink::add_telemetry_callback(TelemetryCallback callback) {
  return impl_->add_callback(std::move(callback), nullptr);
}
int SerialLink::add_state_callback(StateCallback callback) {
  return impl_->add_callback(nullptr, std::move(callback));
}
void SerialLink::remove_callback(int id) { impl_->remove_callback(id); }
LinkState SerialLink::state() const { return impl_->state(); }
SerialLink::Counters SerialLink::counters() const { return impl_->counters(); }
boost::asio::io_context& SerialLink::io_context() { return impl_->io(); }

}  // namespace marvin::devices
