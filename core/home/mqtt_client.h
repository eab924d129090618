// An MQTT client on libmosquitto, driven by a Boost.Asio io_context (the home service's
// event loop): the socket is watched with async_wait, keep-alive runs on a timer, and a
// lost or refused connection is retried in the background with back-off (0.1 s doubling
// to 2 s), so a broker that comes back is reconnected within about 2 s.
//
// Every libmosquitto call happens on the io_context's thread; subscribe() and publish()
// may be called from any thread (they are posted). Subscriptions are remembered and made
// again after each reconnect. Publishing while disconnected drops the message and
// publish() says so: a device command must not be queued and carried out late, after the
// user has been told it failed.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

struct mosquitto;
struct mosquitto_message;

namespace marvin::home {

struct MqttOptions {
  std::string host = "127.0.0.1";
  int port = 1883;
  std::string client_id;  // empty: libmosquitto makes one up
  std::string user;       // empty: no authentication
  std::string password;
  // TLS: on when `tls` is set; `ca_file` empty means the system's CA certificates.
  bool tls = false;
  std::string ca_file;
  int keepalive_s = 10;
  // The last will, published by the broker when this client vanishes (retained).
  std::string will_topic;
  std::string will_payload;
  // Sent first on every connection (retained), e.g. "online" on the will's topic.
  std::string birth_topic;
  std::string birth_payload;
};

class MqttClient {
 public:
  // (topic, payload, retained), on the io_context's thread.
  using MessageHandler = std::function<void(const std::string&, std::string_view, bool)>;
  // true once connected and every subscription acknowledged by the broker (so a message
  // published after it reaches this client), false when the connection is lost.
  using ConnectionHandler = std::function<void(bool)>;

  MqttClient(boost::asio::io_context& io, MqttOptions options, MessageHandler on_message,
             ConnectionHandler on_connection);
  ~MqttClient();  // call stop() first, with the io_context still running or stopped
  MqttClient(const MqttClient&) = delete;
  MqttClient& operator=(const MqttClient&) = delete;

  // Starts connecting (posted). Throws std::runtime_error for options libmosquitto refuses.
  void start();
  // Disconnects cleanly (the will is not sent) and stops retrying. Blocks until done when
  // called from another thread while the io_context runs.
  void stop();

  void subscribe(std::string topic_filter);
  // Queues the message; false (and nothing sent) when not connected.
  bool publish(std::string topic, std::string payload, int qos = 0, bool retain = false);

  bool connected() const { return connected_.load(); }
  // How many times the connection came up (1 after the first connect).
  int connections() const { return connections_.load(); }

 private:
  static void on_connect_cb(mosquitto*, void* self, int rc);
  static void on_disconnect_cb(mosquitto*, void* self, int rc);
  static void on_subscribe_cb(mosquitto*, void* self, int mid, int count, const int* granted);
  static void on_message_cb(mosquitto*, void* self, const mosquitto_message* message);

  void connect();         // io thread
  void schedule_retry();  // io thread
  void watch();           // io thread: (re)arms the socket waits for the current fd
  void after_io(int rc);  // io thread
  void lost();            // io thread
  void release_socket();
  void tick();
  void ready();  // io thread: connected and subscribed

  boost::asio::io_context& io_;
  MqttOptions options_;
  MessageHandler on_message_;
  ConnectionHandler on_connection_;
  mosquitto* mosq_ = nullptr;
  std::optional<boost::asio::posix::stream_descriptor> socket_;
  int fd_ = -1;
  unsigned generation_ = 0;
  bool reading_ = false;
  bool writing_ = false;
  bool stopped_ = false;
  bool session_up_ = false;  // io thread: CONNACK seen on this socket
  std::vector<int> pending_subacks_;  // io thread: SUBSCRIBE ids of this connection
  std::chrono::milliseconds backoff_{100};
  boost::asio::steady_timer retry_timer_;
  boost::asio::steady_timer tick_timer_;
  std::vector<std::string> subscriptions_;  // io thread
  std::atomic<bool> connected_{false};
  std::atomic<int> connections_{0};
};

}  // namespace marvin::home
