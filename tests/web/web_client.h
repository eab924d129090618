// A small HTTPS client for the web tests: one connection per request, the server's generated
// certificate as the only trusted one, and a watchdog that ends a read that hangs (so a
// server bug fails the test instead of blocking it).
#pragma once

#include <sys/socket.h>

// clang-format off
#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange
// clang-format on
#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace marvin::web::test {

namespace asio = boost::asio;
namespace ssl = asio::ssl;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

// Shuts the socket down (the blocked read returns) unless cancelled within `timeout`.
class Watchdog {
 public:
  Watchdog(int fd, std::chrono::seconds timeout)
      : thread_([this, fd, timeout] {
          std::unique_lock lock(mutex_);
          if (!cv_.wait_for(lock, timeout, [this] { return done_; })) ::shutdown(fd, SHUT_RDWR);
        }) {}
  ~Watchdog() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool done_ = false;
  std::thread thread_;
};

struct Reply {
  unsigned status = 0;
  std::string body;
  std::string set_cookie;
  std::string content_type;
  nlohmann::json json() const { return nlohmann::json::parse(body); }
  std::string error() const { return json().value("error", std::string()); }
};

// One TLS connection to 127.0.0.1:port, trusting only `cert`.
class Connection {
 public:
  Connection(std::uint16_t port, const std::filesystem::path& cert)
      : ctx_(ssl::context::tls_client), stream_(ioc_, ctx_) {
    ctx_.load_verify_file(cert.string());
    stream_.set_verify_mode(ssl::verify_peer);
    stream_.next_layer().connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    watchdog_.emplace(stream_.next_layer().native_handle(), std::chrono::seconds(20));
    stream_.handshake(ssl::stream_base::client);
  }
  ssl::stream<tcp::socket>& stream() { return stream_; }

  void write(const std::string& raw) { asio::write(stream_, asio::buffer(raw)); }

  Reply read_reply() {
    http::response<http::string_body> res;
    http::read(stream_, buffer_, res);
    Reply r;
    r.status = res.result_int();
    r.body = res.body();
    r.set_cookie = std::string(res[http::field::set_cookie]);
    r.content_type = std::string(res[http::field::content_type]);
    return r;
  }

  // The next Server-Sent Event after the response head: {kind, data}.
  std::pair<std::string, std::string> next_event() {
    if (!head_read_) {
      asio::read_until(stream_, asio::dynamic_buffer(pending_), "\r\n\r\n");
      pending_.erase(0, pending_.find("\r\n\r\n") + 4);
      head_read_ = true;
    }
    asio::read_until(stream_, asio::dynamic_buffer(pending_), "\n\n");
    const std::string message = pending_.substr(0, pending_.find("\n\n"));
    pending_.erase(0, message.size() + 2);
    std::string kind, data;
    for (std::size_t start = 0; start < message.size();) {
      std::size_t end = message.find('\n', start);
      if (end == std::string::npos) end = message.size();
      const std::string line = message.substr(start, end - start);
      if (line.rfind("event: ", 0) == 0) kind = line.substr(7);
      if (line.rfind("data: ", 0) == 0) data = line.substr(6);
      start = end + 1;
    }
    return {kind, data};
  }

 private:
  asio::io_context ioc_;
  ssl::context ctx_;
  ssl::stream<tcp::socket> stream_;
  beast::flat_buffer buffer_;
  std::optional<Watchdog> watchdog_;
  std::string pending_;
  bool head_read_ = false;
};

// A browser's view: the session cookie and CSRF token after login().
class Browser {
 public:
  Browser(std::uint16_t port, std::filesystem::path cert)
      : port_(port), cert_(std::move(cert)), origin_("https://127.0.0.1:" + std::to_string(port)) {}

  Reply send(const std::string& method, const std::string& target, const std::string& body = "",
             std::vector<std::pair<std::string, std::string>> headers = {}) {
    Connection c(port_, cert_);
    std::string raw = method + " " + target +
                      " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port_) +
                      "\r\nConnection: close\r\n";
    bool has_origin = false;
    for (const auto& [name, value] : headers) {
      raw += name + ": " + value + "\r\n";
      has_origin = has_origin || name == "Origin";
    }
    if (!has_origin && method != "GET") raw += "Origin: " + origin_ + "\r\n";
    if (!cookie.empty()) raw += "Cookie: " + cookie + "\r\n";
    if (!csrf.empty() && method != "GET" && !no_csrf) raw += "X-CSRF-Token: " + csrf + "\r\n";
    raw += "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
    c.write(raw);
    return c.read_reply();
  }

  Reply login(const std::string& password) {
    Reply r = send("POST", "/api/login", nlohmann::json{{"password", password}}.dump());
    if (r.status == 200) {
      cookie = r.set_cookie.substr(0, r.set_cookie.find(';'));
      csrf = r.json()["csrf"].get<std::string>();
    }
    return r;
  }

  // GET /api/live on a connection of its own, kept open by the caller.
  std::unique_ptr<Connection> open_live() {
    auto c = std::make_unique<Connection>(port_, cert_);
    c->write("GET /api/live HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port_) +
             "\r\nCookie: " + cookie + "\r\n\r\n");
    return c;
  }

  std::string cookie;
  std::string csrf;
  bool no_csrf = false;

 private:
  std::uint16_t port_;
  std::filesystem::path cert_;
  std::string origin_;
};

}  // namespace marvin::web::test
