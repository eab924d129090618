#include "web/web_server.h"

#include <sys/inotify.h>
#include <unistd.h>

// clang-format off
#include <utility>  // before Asio: Boost 1.74's awaitable.hpp uses std::exchange
// clang-format on
#include <array>
#include <atomic>
#include <boost/asio.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <cstring>
#include <deque>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include "data/personal_data.h"
#include "data/sqlite_store.h"
#include "skills/smart_home.h"
#include "web/api.h"
#include "web/live.h"
#include "web/tls.h"

namespace marvin::web {

namespace fs = std::filesystem;
namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace ssl = asio::ssl;
using tcp = asio::ip::tcp;
using nlohmann::json;

fs::path web_state_dir(const fs::path& data_dir) { return data_dir / "web"; }
fs::path password_file(const fs::path& state_dir) { return state_dir / "password"; }

fs::path default_static_dir() {
  if (const char* root = std::getenv("MARVIN_WEB_ROOT"); root && *root) return root;
  return MARVIN_WEB_STATIC_DIR;
}

namespace {

constexpr std::size_t kRequestLimit = 64 * 1024;  // every request but a skill upload
constexpr std::size_t kLiveQueueLimit = 512;      // messages a slow page may lag behind
constexpr const char* kCookie = "marvin_session";

struct Listen {
  std::string address;
  std::uint16_t port = 0;
};

Listen parse_listen(const std::string& text) {
  const auto colon = text.rfind(':');
  const std::string port = colon == std::string::npos ? "" : text.substr(colon + 1);
  std::string address = colon == std::string::npos ? "" : text.substr(0, colon);
  if (address.size() > 2 && address.front() == '[' && address.back() == ']')
    address = address.substr(1, address.size() - 2);
  if (address.empty() || port.empty() || port.size() > 5 ||
      port.find_first_not_of("0123456789") != std::string::npos || std::stoul(port) > 65535)
    throw std::runtime_error("web listen address '" + text +
                             "' is not ADDR:PORT (e.g. 127.0.0.1:8443 or 0.0.0.0:8443)");
  return {address, static_cast<std::uint16_t>(std::stoul(port))};
}

std::string content_type(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  return "application/octet-stream";
}

std::string cookie_value(std::string_view header, std::string_view name) {
  while (!header.empty()) {
    const auto semi = header.find(';');
    std::string_view part = header.substr(0, semi);
    while (!part.empty() && part.front() == ' ') part.remove_prefix(1);
    if (part.size() > name.size() && part.substr(0, name.size()) == name &&
        part[name.size()] == '=')
      return std::string(part.substr(name.size() + 1));
    if (semi == std::string_view::npos) break;
    header.remove_prefix(semi + 1);
  }
  return {};
}

std::map<std::string, std::string> parse_query(std::string_view query) {
  std::map<std::string, std::string> out;
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const auto eq = pair.find('=');
    if (!pair.empty())
      out[url_decode(pair.substr(0, eq))] =
          eq == std::string_view::npos ? "" : url_decode(pair.substr(eq + 1));
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return out;
}

}  // namespace

class WebConnection;

struct WebServer::Impl {
  Impl(WebOptions o, data::PersonalData& d, data::SqliteStore& s, LiveFeed* f)
      : options(std::move(o)),
        data(d),
        store(s),
        feed(f),
        api(options, data, store, feed),
        sessions(options.session_ttl),
        limiter(options.login_attempts_per_minute) {}

  Clock::time_point now() const { return options.now ? options.now() : Clock::now(); }
  void accept();
  // Reads the event log's new entries and sends them to the open pages (server's thread).
  void read_new_events();
  // Any thread: posts one read_new_events() unless one is already waiting to run.
  void wake_for_events();
  // Events written by other processes on the same file: inotify on the database's folder
  // (each commit writes the WAL), read on the server's thread.
  void watch_other_writers();
  void read_file_changes();
  void recheck_after_change(std::size_t round);
  void broadcast(const std::string& kind, const json& update);

  WebOptions options;
  data::PersonalData& data;
  data::SqliteStore& store;
  LiveFeed* feed;
  Api api;
  asio::io_context ioc;
  ssl::context tls{ssl::context::tls_server};
  std::optional<tcp::acceptor> acceptor;
  std::uint64_t events_watch = 0;               // the store's events_written() token
  std::atomic<bool> events_read_queued{false};  // a read_new_events() is posted, not yet run
  std::atomic<bool> devices_change_queued{false};  // a "changed devices" is posted, not yet sent
  std::optional<asio::posix::stream_descriptor> file_changes;  // inotify, or none
  std::optional<asio::steady_timer> recheck_timer;             // re-reads after a change
  std::string db_name;                                         // "marvin.db"
  std::array<char, 4096> file_change_buffer;
  std::thread thread;
  std::uint16_t port = 0;
  bool running = false;
  bool stopping = false;  // on the server's thread: no new accepts or reads
  Sessions sessions;
  LoginLimiter limiter;
  std::int64_t last_event_id = 0;
  std::set<std::shared_ptr<WebConnection>> live;                          // open live pages
  std::set<std::weak_ptr<WebConnection>, std::owner_less<>> connections;  // for stop()
  std::atomic<std::size_t> live_count{0};
};

// One HTTPS connection: requests one after the other (keep-alive), or, after GET /api/live,
// a stream of Server-Sent Events until the page closes.
class WebConnection : public std::enable_shared_from_this<WebConnection> {
 public:
  WebConnection(WebServer::Impl& server, tcp::socket socket)
      : server_(server), stream_(std::move(socket), server.tls) {
    beast::error_code ec;
    const auto remote = beast::get_lowest_layer(stream_).socket().remote_endpoint(ec);
    client_ = ec ? "unknown" : remote.address().to_string();
  }

  void start() {
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
    stream_.async_handshake(ssl::stream_base::server,
                            [self = shared_from_this()](beast::error_code ec) {
                              if (!ec) self->read_header();
                            });
  }

  void close() {
    beast::error_code ec;
    beast::get_lowest_layer(stream_).socket().shutdown(tcp::socket::shutdown_both, ec);
    beast::get_lowest_layer(stream_).close();
  }

  // Queues one Server-Sent Event; false when the page lags too far behind or its session
  // ended (the caller drops it).
  bool send_event(const std::string& kind, const json& data) {
    if (!server_.sessions.find(session_id_, server_.now())) return false;
    if (queue_.size() >= kLiveQueueLimit) return false;
    queue_.push_back("event: " + kind + "\ndata: " + data.dump() + "\n\n");
    write_next();
    return true;
  }

 private:
  using Response = http::response<http::string_body>;

  void read_header() {
    parser_.emplace();
    parser_->header_limit(16 * 1024);
    // No limit while reading the head (Beast would refuse a large Content-Length without a
    // word); on_header() answers 413 and then sets the limit for the body.
    parser_->body_limit(std::numeric_limits<std::uint64_t>::max());
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(60));
    http::async_read_header(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
  }

  void on_header(beast::error_code ec) {
    if (ec) return close();
    const auto& req = parser_->get();
    const std::string target(req.target());
    const bool upload = target.rfind("/api/skills/install", 0) == 0 ||
                        target.rfind("/api/people/enroll", 0) == 0;
    const std::size_t limit = upload ? server_.options.upload_limit : kRequestLimit;
    // Refused from the headers: a large body is never read, let alone stored.
    if (const auto length = parser_->content_length(); length && *length > limit)
      return refuse_too_large(*length, limit);
    parser_->body_limit(limit);
    beast::get_lowest_layer(stream_).expires_after(std::chrono::minutes(5));
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this(), limit](beast::error_code read_ec, std::size_t) {
                       if (read_ec == http::error::body_limit)
                         return self->refuse_too_large(std::nullopt, limit);
                       if (read_ec) return self->close();
                       self->handle(self->parser_->release());
                     });
  }

  void refuse_too_large(std::optional<std::uint64_t> length, std::size_t limit) {
    const std::string size = length ? std::to_string(*length) + " bytes" : "more than that";
    Response res = error_response(413, "request body too large: " + size + ", at most " +
                                           std::to_string(limit) + " bytes here");
    res.keep_alive(false);
    auto held = std::make_shared<Response>(std::move(res));
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(10));
    http::async_write(
        stream_, *held, [self = shared_from_this(), held](beast::error_code ec, std::size_t) {
          if (ec && ec != http::error::end_of_stream) return self->close();  // "close" is ours
          // Closing with the client's body still arriving would reset the connection and could
          // lose the answer: stop sending, then read and drop what comes (up to 8 MiB or 5 s).
          beast::error_code ignored;
          beast::get_lowest_layer(self->stream_)
              .socket()
              .shutdown(tcp::socket::shutdown_send, ignored);
          beast::get_lowest_layer(self->stream_).expires_after(std::chrono::seconds(5));
          self->drain(8 * 1024 * 1024);
        });
  }

  void drain(std::size_t budget) {
    beast::get_lowest_layer(stream_).async_read_some(
        asio::buffer(drain_buffer_),
        [self = shared_from_this(), budget](beast::error_code ec, std::size_t n) {
          if (ec || n >= budget) return self->close();
          self->drain(budget - n);
        });
  }

  Response base_response(unsigned status) const {
    Response res;
    res.result(status);
    res.version(11);
    res.set(http::field::server, "Marvin");
    res.set(http::field::cache_control, "no-store");
    res.set("X-Content-Type-Options", "nosniff");
    res.set("X-Frame-Options", "DENY");
    res.set("Referrer-Policy", "no-referrer");
    res.set("Content-Security-Policy",
            "default-src 'self'; img-src 'self' data:; frame-ancestors 'none'; form-action 'self'");
    res.set("Strict-Transport-Security", "max-age=31536000");
    return res;
  }

  Response json_response(unsigned status, const json& body) const {
    Response res = base_response(status);
    res.set(http::field::content_type, "application/json; charset=utf-8");
    res.body() = body.dump();
    res.prepare_payload();
    return res;
  }

  Response error_response(unsigned status, const std::string& message) const {
    return json_response(status, {{"error", message}});
  }

  void send(Response res, bool close_after) {
    res.keep_alive(!close_after);
    auto held = std::make_shared<Response>(std::move(res));
    beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(60));
    http::async_write(
        stream_, *held,
        [self = shared_from_this(), held, close_after](beast::error_code ec, std::size_t) {
          if (ec || close_after) return self->close();
          self->read_header();
        });
  }

  Response serve_file(const std::string& path) const {
    std::string name = path == "/" ? "index.html" : path.substr(1);
    const bool plain =
        !name.empty() && name.find("..") == std::string::npos &&
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-.") == std::string::npos;
    const fs::path file = server_.options.static_dir / name;
    std::ifstream in(file, std::ios::binary);
    if (!plain || !in) return error_response(404, "no page " + path);
    Response res = base_response(200);
    res.set(http::field::content_type, content_type(file));
    res.body().assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    res.prepare_payload();
    return res;
  }

  void handle(http::request<http::string_body> req) {
    const bool keep = req.keep_alive();
    const std::string target(req.target());
    const auto question = target.find('?');
    const std::string path = target.substr(0, question);
    const std::string method(req.method_string());

    // Another site's page may not use this one (the browser names it in Origin).
    const std::string host(req[http::field::host]);
    const std::string origin(req[http::field::origin]);
    if (host.empty()) return send(error_response(400, "the request has no Host header"), true);
    const std::string own_origin = "https://" + host;
    // A link from another site opening the page is fine (a top-level GET of a page);
    // anything else the browser marks cross-site is not.
    const bool page_link = method == "GET" && path.rfind("/api/", 0) != 0;
    if ((!origin.empty() && origin != own_origin) ||
        (req["Sec-Fetch-Site"] == "cross-site" && !page_link))
      return send(error_response(
                      403, "request from another origin (" +
                               (origin.empty() || origin == own_origin ? std::string("cross-site")
                                                                       : origin) +
                               ") refused; this page is " + own_origin),
                  !keep);

    if (path == "/login.html" || path == "/style.css" || path == "/login.js")
      return send(serve_file(path), !keep);
    if (path == "/api/login" && method == "POST") return send(login(req), !keep);

    const std::string cookie = cookie_value(std::string(req[http::field::cookie]), kCookie);
    const std::optional<Session> session =
        cookie.empty() ? std::nullopt : server_.sessions.find(cookie, server_.now());
    const bool is_api = path.rfind("/api/", 0) == 0;
    if (!session) {
      if (is_api)
        return send(
            error_response(401, "not logged in, or the session expired: log in at /login.html"),
            !keep);
      Response res = base_response(302);
      res.set(http::field::location, "/login.html");
      res.prepare_payload();
      return send(std::move(res), !keep);
    }
    if (!is_api) {
      if (method != "GET")
        return send(error_response(405, method + " " + path + ": pages are only read"), !keep);
      return send(serve_file(path), !keep);
    }
    if (method != "GET") {
      const std::string token(req["X-CSRF-Token"]);
      if (token.empty())
        return send(
            error_response(403, "missing CSRF token (X-CSRF-Token header); nothing was changed"),
            !keep);
      if (!same_token(token, session->csrf))
        return send(
            error_response(403, "wrong CSRF token (X-CSRF-Token header); nothing was changed"),
            !keep);
    }
    if (path == "/api/session" && method == "GET") {
      const auto left =
          std::chrono::duration_cast<std::chrono::seconds>(session->expires - server_.now());
      return send(json_response(200, {{"csrf", session->csrf}, {"expires_in_s", left.count()}}),
                  !keep);
    }
    if (path == "/api/logout" && method == "POST") {
      server_.sessions.remove(session->id);
      Response res = json_response(200, {{"logged_out", true}});
      res.set(http::field::set_cookie,
              std::string(kCookie) + "=; Path=/; Secure; HttpOnly; SameSite=Strict; Max-Age=0");
      return send(std::move(res), !keep);
    }
    if (path == "/api/live" && method == "GET") return start_live(session->id);

    ApiRequest api{method, path, {}, std::move(req.body()), std::string(req["X-Marvin-Signature"])};
    try {
      if (question != std::string::npos)
        api.query = parse_query(std::string_view(target).substr(question + 1));
    } catch (const std::exception& e) {
      return send(error_response(400, std::string("query: ") + e.what()), !keep);
    }
    ApiResponse out = server_.api.handle(api);
    if (!out.content_type.empty()) {
      Response res = base_response(out.status);
      res.set(http::field::content_type, out.content_type);
      res.body() = std::move(out.raw);
      res.prepare_payload();
      return send(std::move(res), !keep);
    }
    if (method != "GET" && out.status < 300) {
      // Other open pages refresh what changed ("reminders", "contacts", "skills").
      const std::string what = path.substr(
          5, path.find('/', 5) == std::string::npos ? std::string::npos : path.find('/', 5) - 5);
      server_.broadcast("changed", {{"what", what}});
    }
    send(json_response(out.status, out.body), !keep);
  }

  Response login(const http::request<http::string_body>& req) {
    const auto now = server_.now();
    if (const auto wait = server_.limiter.wait_time(client_, now))
      return error_response(429, "too many failed logins from " + client_ + "; try again in " +
                                     std::to_string(wait->count()) + " s");
    std::string password;
    try {
      const json doc = json::parse(req.body());
      if (!doc.is_object() || !doc.contains("password") || !doc["password"].is_string())
        return error_response(400, "field 'password': missing");
      password = doc["password"].get<std::string>();
    } catch (const json::parse_error& e) {
      return error_response(400, std::string("request body: not valid JSON (") + e.what() + ")");
    }
    const fs::path file = password_file(server_.options.state_dir);
    if (!password_is_set(file))
      return error_response(401, "no password is set: run `marvin web password` on the robot");
    if (!check_password(file, password)) {
      server_.limiter.failed(client_, now);
      return error_response(401, "wrong password");
    }
    server_.limiter.succeeded(client_);
    const Session s = server_.sessions.create(now);
    Response res = json_response(200, {{"csrf", s.csrf}});
    res.set(http::field::set_cookie, std::string(kCookie) + "=" + s.id +
                                         "; Path=/; Secure; HttpOnly; SameSite=Strict; Max-Age=" +
                                         std::to_string(server_.sessions.ttl().count()));
    return res;
  }

  void start_live(const std::string& session_id) {
    session_id_ = session_id;
    beast::get_lowest_layer(stream_).expires_never();
    queue_.push_back(
        "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n"
        "X-Content-Type-Options: nosniff\r\nConnection: keep-alive\r\n\r\n");
    json first = server_.feed ? server_.feed->snapshot()
                              : json{{"light", "off"}, {"doing", ""}, {"turns", json::array()}};
    first["running"] = server_.feed != nullptr;
    queue_.push_back("event: hello\ndata: " + first.dump() + "\n\n");
    server_.live.insert(shared_from_this());
    server_.live_count = server_.live.size();
    write_next();
    // The page sends nothing more: a read ends only when it goes away.
    stream_.async_read_some(
        asio::buffer(discard_),
        [self = shared_from_this()](beast::error_code, std::size_t) { self->drop_live(); });
  }

  void drop_live() {
    server_.live.erase(shared_from_this());
    server_.live_count = server_.live.size();
    close();
  }

  void write_next() {
    if (writing_ || queue_.empty()) return;
    writing_ = true;
    asio::async_write(stream_, asio::buffer(queue_.front()),
                      [self = shared_from_this()](beast::error_code ec, std::size_t) {
                        self->writing_ = false;
                        self->queue_.pop_front();
                        if (ec) return self->drop_live();
                        self->write_next();
                      });
  }

  WebServer::Impl& server_;
  beast::ssl_stream<beast::tcp_stream> stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::string client_;
  std::string session_id_;
  std::deque<std::string> queue_;
  bool writing_ = false;
  char discard_[64];
  std::array<char, 16 * 1024> drain_buffer_;
};

void WebServer::Impl::accept() {
  acceptor->async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec || stopping) return;  // closed by stop()
    auto connection = std::make_shared<WebConnection>(*this, std::move(socket));
    for (auto it = connections.begin(); it != connections.end();)
      it = it->expired() ? connections.erase(it) : std::next(it);
    connections.insert(connection);
    connection->start();
    accept();
  });
}

void WebServer::Impl::broadcast(const std::string& kind, const json& update) {
  for (auto it = live.begin(); it != live.end();) {
    if ((*it)->send_event(kind, update)) {
      ++it;
    } else {
      (*it)->close();
      it = live.erase(it);
    }
  }
  live_count = live.size();
}

void WebServer::Impl::wake_for_events() {
  if (!events_read_queued.exchange(true)) asio::post(ioc, [this] { read_new_events(); });
}

void WebServer::Impl::read_new_events() {
  events_read_queued = false;  // before reading: a write from now on posts another read
  if (stopping) return;
  try {
    std::vector<data::Event> fresh;
    for (const data::Event& e : store.recent_events(50)) {
      if (e.id <= last_event_id) break;
      fresh.push_back(e);
    }
    for (auto it = fresh.rbegin(); it != fresh.rend(); ++it) {
      last_event_id = std::max(last_event_id, it->id);
      broadcast("event",
                api.event_json(it->id, it->time_utc_ms, it->kind, it->source, it->message));
    }
  } catch (const std::exception&) {
    // A busy or failing database is reported by the page's next request; the next event
    // written reads again from the same point.
  }
}

void WebServer::Impl::watch_other_writers() {
  const int fd = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd < 0) return;  // no live events from other processes; this one's still come
  const fs::path db = store.path();
  if (::inotify_add_watch(fd, db.parent_path().c_str(), IN_MODIFY | IN_CLOSE_WRITE) < 0) {
    ::close(fd);
    return;
  }
  db_name = db.filename().string();
  file_changes.emplace(ioc, fd);
  recheck_timer.emplace(ioc);
  read_file_changes();
}

void WebServer::Impl::read_file_changes() {
  file_changes->async_read_some(
      asio::buffer(file_change_buffer), [this](beast::error_code ec, std::size_t n) {
        if (ec || stopping) return;
        // Records: struct inotify_event, then its name (padded). The database or its WAL
        // changed (anyone's commit, ours too): read now and re-check shortly after.
        for (std::size_t at = 0; at + sizeof(inotify_event) <= n;) {
          inotify_event head;
          std::memcpy(&head, file_change_buffer.data() + at, sizeof head);
          const char* name = file_change_buffer.data() + at + sizeof head;
          if (head.len && std::string(name, strnlen(name, head.len)).rfind(db_name, 0) == 0) {
            wake_for_events();
            recheck_after_change(0);
            break;
          }
          at += sizeof head + head.len;
        }
        read_file_changes();
      });
}

void WebServer::Impl::recheck_after_change(std::size_t round) {
  // Another process's commit becomes visible when it updates the shared WAL index (memory
  // mapped, so inotify does not see it), just after its last file write and fsync: look
  // again 50, 250 and 1000 ms after the last change, then rest until the next change.
  static constexpr std::array<int, 3> kAfterMs = {50, 250, 1000};
  if (round >= kAfterMs.size()) return;
  recheck_timer->expires_after(std::chrono::milliseconds(kAfterMs[round]));
  recheck_timer->async_wait([this, round](beast::error_code ec) {
    if (ec || stopping) return;  // cancelled by a newer change (which starts again) or stop
    wake_for_events();
    recheck_after_change(round + 1);
  });
}

WebServer::WebServer(WebOptions options, data::PersonalData& data, data::SqliteStore& store,
                     LiveFeed* feed)
    : impl_(std::make_unique<Impl>(std::move(options), data, store, feed)) {
  if (impl_->options.static_dir.empty()) impl_->options.static_dir = default_static_dir();
}

WebServer::~WebServer() { stop(); }

void WebServer::start() {
  Impl& s = *impl_;
  if (s.running) return;
  const Listen listen = parse_listen(s.options.listen);
  fs::path cert = s.options.cert_file, key = s.options.key_file;
  if (cert.empty() != key.empty())
    throw std::runtime_error("web certificate: give both the certificate and its key, or neither");
  if (cert.empty()) {
    cert = s.options.state_dir / "cert.pem";
    key = s.options.state_dir / "key.pem";
    if (!fs::exists(cert) || !fs::exists(key)) {
      std::vector<std::string> names = {"localhost", "127.0.0.1", "::1"};
      if (listen.address != "0.0.0.0" && listen.address != "::" && listen.address != "127.0.0.1")
        names.push_back(listen.address);
      char host[256] = {};
      if (::gethostname(host, sizeof host - 1) == 0 && host[0]) {
        names.emplace_back(host);
        names.push_back(std::string(host) + ".local");
      }
      make_self_signed_certificate(cert, key, names);
    }
  }
  try {
    s.tls.set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                      ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1);
    s.tls.use_certificate_chain_file(cert.string());
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error("web certificate " + cert.string() + ": " + e.what());
  }
  try {
    s.tls.use_private_key_file(key.string(), ssl::context::pem);
  } catch (const boost::system::system_error& e) {
    throw std::runtime_error("web certificate key " + key.string() + ": " + e.what());
  }
  try {
    const tcp::endpoint endpoint(asio::ip::make_address(listen.address), listen.port);
    s.acceptor.emplace(s.ioc);
    s.acceptor->open(endpoint.protocol());
    s.acceptor->set_option(asio::socket_base::reuse_address(true));
    s.acceptor->bind(endpoint);
    s.acceptor->listen();
    s.port = s.acceptor->local_endpoint().port();
  } catch (const boost::system::system_error& e) {
    s.acceptor.reset();
    throw std::runtime_error("web page: cannot listen on " + s.options.listen + ": " + e.what());
  }
  for (const data::Event& e : s.store.recent_events(1)) s.last_event_id = e.id;
  s.accept();
  // The store tells when this process wrote events; the read happens on the server's
  // thread, and a burst of writes before it runs is one read. Nothing runs while idle.
  s.events_watch = s.store.events_written().watch([&s] { s.wake_for_events(); });
  s.watch_other_writers();
  // A device switched by voice, a skill, the CLI or another app: open Devices pages reload,
  // as after a change on another page (one "changed" per burst of reports).
  if (s.options.smart_home)
    s.options.smart_home->on_change([&s] {
      if (!s.devices_change_queued.exchange(true))
        asio::post(s.ioc, [&s] {
          s.devices_change_queued = false;
          if (!s.stopping) s.broadcast("changed", {{"what", "devices"}});
        });
    });
  if (s.feed) {
    s.feed->set_listener([&s](const std::string& kind, const json& update) {
      asio::post(s.ioc, [&s, kind, update] { s.broadcast(kind, update); });
    });
  }
  s.running = true;
  s.thread = std::thread([&s] { s.ioc.run(); });
}

void WebServer::stop() {
  Impl& s = *impl_;
  if (!s.running) return;
  if (s.feed) s.feed->set_listener(nullptr);
  if (s.options.smart_home) s.options.smart_home->on_change(nullptr);
  s.store.events_written().unwatch(s.events_watch);
  asio::post(s.ioc, [&s] {
    // A timer or accept that completed just before is already queued: the flag stops it
    // from starting the next round.
    s.stopping = true;
    beast::error_code ec;
    s.acceptor->close(ec);
    if (s.file_changes) s.file_changes->close(ec);
    if (s.recheck_timer) s.recheck_timer->cancel();
    for (const auto& weak : s.connections)
      if (auto c = weak.lock()) c->close();
    s.live.clear();
    s.live_count = 0;
  });
  s.thread.join();
  s.running = false;
}

std::uint16_t WebServer::port() const { return impl_->port; }

std::string WebServer::url() const {
  std::string address = parse_listen(impl_->options.listen).address;
  if (address == "0.0.0.0") address = "127.0.0.1";
  if (address.find(':') != std::string::npos) address = "[" + address + "]";
  return "https://" + address + ":" + std::to_string(impl_->port) + "/";
}

std::size_t WebServer::live_pages() const { return impl_->live_count.load(); }

}  // namespace marvin::web
