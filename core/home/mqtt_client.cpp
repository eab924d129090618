#include "home/mqtt_client.h"

#include <mosquitto.h>

#include <boost/asio/post.hpp>
#include <algorithm>
#include <future>
#include <mutex>
#include <stdexcept>

#include "common/log.h"

namespace marvin::home {
namespace {

constexpr std::chrono::milliseconds kFirstBackoff{100};
constexpr std::chrono::milliseconds kMaxBackoff{2000};
constexpr std::chrono::milliseconds kTick{500};

void init_library() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

std::string describe(int rc) {
  if (rc == MOSQ_ERR_ERRNO) return std::string(mosquitto_strerror(rc)) + " (system error)";
  return mosquitto_strerror(rc);
}

}  // namespace

MqttClient::MqttClient(boost::asio::io_context& io, MqttOptions options,
                       MessageHandler on_message, ConnectionHandler on_connection)
    : io_(io),
      options_(std::move(options)),
      on_message_(std::move(on_message)),
      on_connection_(std::move(on_connection)),
      retry_timer_(io),
      tick_timer_(io) {
  init_library();
  mosq_ = mosquitto_new(options_.client_id.empty() ? nullptr : options_.client_id.c_str(), true,
                        this);
  if (!mosq_) throw std::runtime_error("mqtt: cannot create a libmosquitto client");
  mosquitto_int_option(mosq_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V311);
  mosquitto_connect_callback_set(mosq_, &MqttClient::on_connect_cb);
  mosquitto_disconnect_callback_set(mosq_, &MqttClient::on_disconnect_cb);
  mosquitto_message_callback_set(mosq_, &MqttClient::on_message_cb);
  mosquitto_subscribe_callback_set(mosq_, &MqttClient::on_subscribe_cb);
  int rc = MOSQ_ERR_SUCCESS;
  if (!options_.user.empty()) {
    rc = mosquitto_username_pw_set(mosq_, options_.user.c_str(),
                                   options_.password.empty() ? nullptr : options_.password.c_str());
    if (rc != MOSQ_ERR_SUCCESS) throw std::runtime_error("mqtt: user/password: " + describe(rc));
  }
  if (options_.tls) {
    // No CA file given: the system's certificate directory.
    rc = mosquitto_tls_set(mosq_, options_.ca_file.empty() ? nullptr : options_.ca_file.c_str(),
                           options_.ca_file.empty() ? "/etc/ssl/certs" : nullptr, nullptr,
                           nullptr, nullptr);
    if (rc != MOSQ_ERR_SUCCESS) {
      throw std::runtime_error("mqtt: TLS with CA file '" + options_.ca_file +
                               "': " + describe(rc));
    }
  }
  if (!options_.will_topic.empty()) {
    rc = mosquitto_will_set(mosq_, options_.will_topic.c_str(),
                            static_cast<int>(options_.will_payload.size()),
                            options_.will_payload.data(), 1, true);
    if (rc != MOSQ_ERR_SUCCESS) {
      throw std::runtime_error("mqtt: last will on '" + options_.will_topic +
                               "': " + describe(rc));
    }
  }
}

MqttClient::~MqttClient() {
  release_socket();
  if (mosq_) mosquitto_destroy(mosq_);
}

void MqttClient::start() {
  boost::asio::post(io_, [this] {
    connect();
    tick();
  });
}

void MqttClient::stop() {
  auto work = [this] {
    if (stopped_) return;
    stopped_ = true;
    retry_timer_.cancel();
    tick_timer_.cancel();
    if (session_up_) {
      mosquitto_disconnect(mosq_);
      // Flush the DISCONNECT (a blocking-free best effort: the socket is writable normally).
      mosquitto_loop_write(mosq_, 1);
    }
    release_socket();
    session_up_ = false;
    connected_.store(false);
  };
  if (io_.stopped() || io_.get_executor().running_in_this_thread()) {
    work();
    return;
  }
  std::promise<void> done;
  std::future<void> finished = done.get_future();
  boost::asio::post(io_, [&] {
    work();
    done.set_value();
  });
  // The io_context may stop before it runs the handler: then do it here.
  if (finished.wait_for(std::chrono::seconds(5)) != std::future_status::ready) work();
}

void MqttClient::subscribe(std::string topic_filter) {
  boost::asio::post(io_, [this, topic = std::move(topic_filter)] {
    subscriptions_.push_back(topic);
    if (session_up_) {
      mosquitto_subscribe(mosq_, nullptr, topic.c_str(), 0);
      watch();
    }
  });
}

bool MqttClient::publish(std::string topic, std::string payload, int qos, bool retain) {
  if (!connected_.load()) return false;
  boost::asio::post(io_, [this, topic = std::move(topic), payload = std::move(payload), qos,
                          retain] {
    if (!session_up_) return;
    int rc = mosquitto_publish(mosq_, nullptr, topic.c_str(), static_cast<int>(payload.size()),
                               payload.data(), qos, retain);
    if (rc != MOSQ_ERR_SUCCESS) {
      log(LogLevel::kWarning, "mqtt", "cannot publish to " + topic + ": " + describe(rc));
    }
    watch();
  });
  return true;
}

void MqttClient::connect() {
  if (stopped_) return;
  release_socket();
  int rc = mosquitto_connect_async(mosq_, options_.host.c_str(), options_.port,
                                   options_.keepalive_s);
  if (rc != MOSQ_ERR_SUCCESS) {
    log(LogLevel::kInfo, "mqtt",
        "cannot connect to " + options_.host + ":" + std::to_string(options_.port) + ": " +
            describe(rc) + "; retrying in " + std::to_string(backoff_.count()) + " ms");
    schedule_retry();
    return;
  }
  watch();
}

void MqttClient::schedule_retry() {
  if (stopped_) return;
  retry_timer_.expires_after(backoff_);
  backoff_ = std::min(backoff_ * 2, kMaxBackoff);
  retry_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) connect();
  });
}

void MqttClient::release_socket() {
  if (socket_) {
    boost::system::error_code ec;
    socket_->cancel(ec);
    socket_->release();  // libmosquitto owns and closes the descriptor
    socket_.reset();
  }
  fd_ = -1;
  ++generation_;
  reading_ = writing_ = false;
}

void MqttClient::watch() {
  if (stopped_) return;
  int fd = mosquitto_socket(mosq_);
  if (fd != fd_) {
    release_socket();
    if (fd < 0) return;
    fd_ = fd;
    socket_.emplace(io_, fd);
  }
  if (!socket_) return;
  const unsigned generation = generation_;
  if (!reading_) {
    reading_ = true;
    socket_->async_wait(boost::asio::posix::stream_descriptor::wait_read,
                        [this, generation](const boost::system::error_code& ec) {
                          if (generation != generation_ || stopped_) return;
                          reading_ = false;
                          if (ec) return;
                          after_io(mosquitto_loop_read(mosq_, 16));
                        });
  }
  if (!writing_ && mosquitto_want_write(mosq_)) {
    writing_ = true;
    socket_->async_wait(boost::asio::posix::stream_descriptor::wait_write,
                        [this, generation](const boost::system::error_code& ec) {
                          if (generation != generation_ || stopped_) return;
                          writing_ = false;
                          if (ec) return;
                          after_io(mosquitto_loop_write(mosq_, 16));
                        });
  }
}

void MqttClient::after_io(int rc) {
  if (stopped_) return;
  if (rc != MOSQ_ERR_SUCCESS || mosquitto_socket(mosq_) < 0) {
    lost();
    return;
  }
  watch();
}

void MqttClient::lost() {
  release_socket();
  const bool was_up = session_up_;
  session_up_ = false;
  connected_.store(false);
  if (was_up) {
    log(LogLevel::kWarning, "mqtt",
        "lost the broker " + options_.host + ":" + std::to_string(options_.port) +
            "; reconnecting in the background");
    backoff_ = kFirstBackoff;
    if (on_connection_) on_connection_(false);
  }
  schedule_retry();
}

void MqttClient::tick() {
  if (stopped_) return;
  if (mosquitto_socket(mosq_) >= 0) {
    int rc = mosquitto_loop_misc(mosq_);  // keep-alive pings, and their timeout
    if (rc != MOSQ_ERR_SUCCESS && rc != MOSQ_ERR_NO_CONN) {
      lost();
    } else if (mosquitto_socket(mosq_) < 0) {
      lost();
    } else {
      watch();
    }
  }
  tick_timer_.expires_after(kTick);
  tick_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) tick();
  });
}

void MqttClient::on_connect_cb(mosquitto*, void* self, int rc) {
  auto* c = static_cast<MqttClient*>(self);
  if (rc != 0) {
    log(LogLevel::kWarning, "mqtt",
        "the broker " + c->options_.host + ":" + std::to_string(c->options_.port) +
            " refused the connection: " + mosquitto_connack_string(rc));
    return;  // the broker closes the socket; after_io() retries
  }
  c->session_up_ = true;
  c->backoff_ = kFirstBackoff;
  if (!c->options_.birth_topic.empty()) {
    mosquitto_publish(c->mosq_, nullptr, c->options_.birth_topic.c_str(),
                      static_cast<int>(c->options_.birth_payload.size()),
                      c->options_.birth_payload.data(), 1, true);
  }
  c->pending_subacks_.clear();
  for (const std::string& topic : c->subscriptions_) {
    int mid = 0;
    if (mosquitto_subscribe(c->mosq_, &mid, topic.c_str(), 0) == MOSQ_ERR_SUCCESS) {
      c->pending_subacks_.push_back(mid);
    }
  }
  if (c->pending_subacks_.empty()) c->ready();
}

void MqttClient::on_subscribe_cb(mosquitto*, void* self, int mid, int, const int*) {
  auto* c = static_cast<MqttClient*>(self);
  auto& pending = c->pending_subacks_;
  auto it = std::find(pending.begin(), pending.end(), mid);
  if (it == pending.end()) return;
  pending.erase(it);
  if (pending.empty()) c->ready();
}

void MqttClient::ready() {
  MqttClient* c = this;
  c->connected_.store(true);
  c->connections_.fetch_add(1);
  log(LogLevel::kInfo, "mqtt",
      "connected to " + c->options_.host + ":" + std::to_string(c->options_.port));
  if (c->on_connection_) c->on_connection_(true);
}

void MqttClient::on_disconnect_cb(mosquitto*, void*, int) {
  // Handled by after_io()/tick(), which see the closed socket.
}

void MqttClient::on_message_cb(mosquitto*, void* self, const mosquitto_message* message) {
  auto* c = static_cast<MqttClient*>(self);
  if (!c->on_message_ || !message || !message->topic) return;
  std::string_view payload(static_cast<const char*>(message->payload),
                           static_cast<std::size_t>(message->payloadlen));
  if (!message->payload) payload = {};
  c->on_message_(message->topic, payload, message->retain);
}

}  // namespace marvin::home
