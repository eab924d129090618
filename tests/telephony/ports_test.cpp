// The ports race: Marvin chooses free ports, then baresip binds them; when another program
// (another test run, another service) takes one in between, the supervisor chooses new
// ports instead of restarting baresip on the taken ones forever.
#include <arpa/inet.h>
#include <doctest/doctest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <condition_variable>
#include <mutex>

#include "common/log.h"
#include "support/files.h"
#include "telephony/call_fixture.h"

namespace marvin::telephony {
namespace {

using testing::kWait;

// A 127.0.0.1 port held (UDP and TCP) as another program would hold it.
class HeldPort {
 public:
  HeldPort() {
    tcp_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    udp_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t size = sizeof address;
    REQUIRE(::bind(tcp_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
    REQUIRE(::getsockname(tcp_, reinterpret_cast<sockaddr*>(&address), &size) == 0);
    REQUIRE(::bind(udp_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
    port_ = ntohs(address.sin_port);
  }
  ~HeldPort() {
    ::close(tcp_);
    ::close(udp_);
  }
  HeldPort(const HeldPort&) = delete;
  HeldPort& operator=(const HeldPort&) = delete;
  int port() const { return port_; }

 private:
  int tcp_ = -1;
  int udp_ = -1;
  int port_ = 0;
};

// What the "phone" component logs while it lives.
class PhoneLogCapture {
 public:
  PhoneLogCapture() {
    previous_ = set_log_sink([this](LogLevel, std::string_view component, std::string_view text) {
      std::lock_guard lock(mutex_);
      if (component == "phone") text_ += std::string(text) + "\n";
      changed_.notify_all();
    });
  }
  ~PhoneLogCapture() { set_log_sink(previous_); }
  std::string text() {
    std::lock_guard lock(mutex_);
    return text_;
  }
  // True once `needle` was logged `times` times (within kWait).
  bool wait_for(const std::string& needle, int times = 1) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, kWait, [&] {
      int found = 0;
      for (auto at = text_.find(needle); at != std::string::npos; at = text_.find(needle, at + 1)) {
        ++found;
      }
      return found >= times;
    });
  }

 private:
  LogSink previous_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::string text_;
};

// Marvin's phone with ports of its own choosing (sip_port 0), as `marvin run` has it; the
// first port handed out for `pair` (SIP) or not (control) is `held`.
struct PhoneOnHeldPort {
  PhoneOnHeldPort(const std::filesystem::path& dir, int held, bool held_is_sip)
      : phone(
            [&] {
              PhoneSettings s = testing::marvin_settings(dir);
              s.sip_port = 0;
              s.account_uri = "sip:marvin@127.0.0.1";
              return s;
            }(),
            dir / "baresip", [this](const PhoneEvent& e) { events.add(e); }) {
    phone.baresip().set_port_chooser([this, held, held_is_sip](bool pair) {
      if (pair == held_is_sip && !handed_out) {
        handed_out = true;
        return held;
      }
      return pick_free_port(pair);
    });
  }
  testing::EventLog<PhoneEvent> events;
  bool handed_out = false;  // the supervisor's thread, then this one after wait_ready
  Phone phone;
};

TEST_CASE("a SIP port taken before baresip binds it: new ports, said in the log, calls work") {
  test_support::TempDir dir;
  testing::TestPeer peer(dir / "peer", /*auto_answer=*/true);
  PhoneLogCapture log;
  HeldPort held;
  PhoneOnHeldPort marvin(dir / "marvin", held.port(), /*held_is_sip=*/true);
  marvin.phone.start();
  REQUIRE(marvin.phone.wait_ready(kWait));
  CHECK(marvin.handed_out);
  const int port = marvin.phone.baresip().sip_port();
  CHECK(port != held.port());
  // At least one move: another program on this machine may take the next port too.
  CHECK(marvin.phone.baresip().port_changes() >= 1);
  CHECK(marvin.phone.baresip().restarts() == 0);  // nothing was lost: no "service restarted"
  CHECK(log.text().find("SIP port " + std::to_string(held.port()) +
                        " is taken by another program; now port ") != std::string::npos);
  CHECK(log.text().find("now port " + std::to_string(port) + " (new ports ") !=
        std::string::npos);
  CHECK(marvin.phone.dial(peer.uri()) == "");
  std::size_t seen = 0;
  REQUIRE(marvin.events.wait(
      [](const PhoneEvent& e) { return e.kind == PhoneEvent::Kind::kAnswered; }, &seen));
  CHECK(marvin.phone.hang_up());
}

TEST_CASE("a control port taken before baresip binds it: new control port, the phone is ready") {
  test_support::TempDir dir;
  PhoneLogCapture log;
  HeldPort held;
  PhoneOnHeldPort marvin(dir / "marvin", held.port(), /*held_is_sip=*/false);
  marvin.phone.start();
  REQUIRE(marvin.phone.wait_ready(kWait));
  CHECK(marvin.phone.baresip().ctrl_port() != held.port());
  CHECK(marvin.phone.baresip().port_changes() >= 1);  // another program may take the next one too
  CHECK(log.text().find("control port " + std::to_string(held.port()) +
                        " is taken by another program") != std::string::npos);
  // The control socket answers (it is baresip's, not the other program's).
  CHECK(marvin.phone.baresip().command("reginfo").ok);
}

TEST_CASE("a configured SIP port that is taken is kept (it is the user's), not replaced") {
  test_support::TempDir dir;
  PhoneLogCapture log;
  HeldPort held;
  PhoneSettings s = testing::marvin_settings(dir.path());
  s.sip_port = held.port();
  Baresip ua(s, dir / "baresip", nullptr);
  ua.start();
  // Started twice on the held port: restarted as before (after a second), never moved.
  REQUIRE(log.wait_for("SIP port " + std::to_string(held.port()) + ")", 2));
  CHECK(log.text().find("SIP Transport failed: Address already in use") != std::string::npos);
  CHECK(ua.port_changes() == 0);
  CHECK(ua.sip_port() == held.port());
  CHECK_FALSE(ua.wait_ready(std::chrono::milliseconds(0)));
}

}  // namespace
}  // namespace marvin::telephony
