// Calls between two real baresip user agents on 127.0.0.1: Marvin's (a Phone) and a test
// peer that answers, declines or never answers.
#include <doctest/doctest.h>
#include <signal.h>

#include <cmath>

#include "common/log.h"
#include "support/files.h"
#include "telephony/call_fixture.h"
#include "telephony/emergency_call.h"

namespace marvin::telephony {
namespace {

using testing::EventLog;
using testing::kWait;
using testing::TestPeer;
using Kind = PhoneEvent::Kind;

struct MarvinPhone {
  explicit MarvinPhone(const std::filesystem::path& dir, const std::filesystem::path& audio_in = {},
                       std::chrono::milliseconds no_answer = std::chrono::seconds(20))
      : phone(testing::marvin_settings(dir, audio_in), dir / "baresip",
              [this](const PhoneEvent& e) { events.add(e); }, no_answer) {
    phone.start();
    REQUIRE(phone.wait_ready(kWait));
  }
  std::optional<PhoneEvent> wait(Kind kind, std::chrono::milliseconds timeout = kWait) {
    return events.wait([&](const PhoneEvent& e) { return e.kind == kind; }, &seen, timeout);
  }
  // The next "ended" event; the test stops when none comes.
  PhoneEvent wait_ended() {
    const auto ended = wait(Kind::kEnded);
    REQUIRE(ended);
    return *ended;
  }
  std::string uri() { return phone.baresip().settings().account_uri; }
  EventLog<PhoneEvent> events;
  std::size_t seen = 0;
  Phone phone;
};

// Most tests: a test peer and Marvin's phone (playing `marvin_tone_hz`, or ausine's tone
// when 0) in one temporary directory.
struct PhoneLine {
  explicit PhoneLine(bool peer_answers,
                     std::chrono::milliseconds no_answer = std::chrono::seconds(20),
                     double marvin_tone_hz = 0)
      : peer(dir / "peer", peer_answers),
        marvin(dir / "marvin", tone_file(dir.path(), marvin_tone_hz), no_answer) {}
  static std::filesystem::path tone_file(const std::filesystem::path& dir, double hz) {
    if (hz == 0) return {};
    testing::write_tone_wav(dir / "tone.wav", hz, 1.5);
    return dir / "tone.wav";
  }
  test_support::TempDir dir;
  TestPeer peer;
  MarvinPhone marvin;
  std::size_t peer_seen = 0;  // the peer's events read so far
  std::optional<BaresipEvent> peer_event(const std::string& type) {
    return peer.wait_event(type, &peer_seen);
  }
};

TEST_CASE("an answered call carries Marvin's tone to the other side and the other side's back") {
  PhoneLine line(/*peer_answers=*/true, std::chrono::seconds(20), 1000);  // the peer: 440 Hz
  auto& peer = line.peer;
  auto& marvin = line.marvin;
  testing::ClosedFileWatch heard_files(peer.record_dir());
  testing::ClosedFileWatch marvin_heard_files(line.dir / "marvin" / "recordings");

  CHECK(marvin.phone.dial(peer.uri()) == "");
  REQUIRE(marvin.wait(Kind::kAnswered));
  CHECK(marvin.phone.state() == CallState::kInCall);
  CHECK(marvin.phone.peer() == peer.uri());
  // The tone file ends after 1.5 s, and with it the call (baresip 1.0's aufile).
  REQUIRE(line.peer_event("CALL_CLOSED"));
  marvin.wait_ended();
  const auto heard = heard_files.wait("-dec.wav", kWait);
  REQUIRE(heard);
  int rate = 0;
  const auto samples = testing::read_wav(*heard, &rate);
  CHECK(samples.size() > static_cast<std::size_t>(rate) / 2);  // at least half a second
  CHECK(std::abs(testing::dominant_frequency(samples, rate) - 1000) <= 20);
  // And the peer's 440 Hz came back to Marvin's recording.
  const auto marvin_heard = marvin_heard_files.wait("-dec.wav", kWait);
  REQUIRE(marvin_heard);
  const auto back = testing::read_wav(*marvin_heard, &rate);
  CHECK(back.size() > static_cast<std::size_t>(rate) / 2);
  CHECK(std::abs(testing::dominant_frequency(back, rate) - 440) <= 20);
}

TEST_CASE("ringing, then hang up: the other side sees the call end") {
  PhoneLine line(/*peer_answers=*/false);
  auto& marvin = line.marvin;
  CHECK(marvin.phone.dial(line.peer.uri()) == "");
  REQUIRE(line.peer_event("CALL_INCOMING"));
  REQUIRE(marvin.wait(Kind::kRinging));
  CHECK(marvin.phone.state() == CallState::kRinging);
  CHECK(marvin.phone.hang_up());
  CHECK(marvin.wait_ended().end == CallEnd::kHungUp);
  CHECK(line.peer_event("CALL_CLOSED"));
  CHECK(marvin.phone.state() == CallState::kIdle);
  CHECK_FALSE(marvin.phone.hang_up());  // nothing left to hang up
}

TEST_CASE("a declined call is reported busy") {
  PhoneLine line(/*peer_answers=*/false);
  CHECK(line.marvin.phone.dial(line.peer.uri()) == "");
  REQUIRE(line.peer_event("CALL_INCOMING"));
  CHECK(line.peer.ua().command("hangup").ok);
  const PhoneEvent ended = line.marvin.wait_ended();
  CHECK(ended.end == CallEnd::kBusy);
  CHECK(ended.reason.find("486") == 0);
}

TEST_CASE("a call nobody answers ends as 'no answer' after the timeout") {
  PhoneLine line(/*peer_answers=*/false, std::chrono::milliseconds(800));
  CHECK(line.marvin.phone.dial(line.peer.uri()) == "");
  CHECK(line.marvin.wait_ended().end == CallEnd::kNoAnswer);
  CHECK(line.peer_event("CALL_CLOSED"));
}

TEST_CASE("an incoming call is announced, answered, then declined the next time") {
  PhoneLine line(/*peer_answers=*/false);
  auto& peer = line.peer;
  auto& marvin = line.marvin;
  CHECK_FALSE(marvin.phone.answer());  // nothing rings yet
  REQUIRE(peer.ua().command("dial", marvin.uri()).ok);
  const auto incoming = marvin.wait(Kind::kIncoming);
  REQUIRE(incoming);
  CHECK(incoming->peer_uri == peer.ua().settings().account_uri);
  CHECK(marvin.phone.state() == CallState::kIncoming);
  CHECK(marvin.phone.answer());
  REQUIRE(marvin.wait(Kind::kAnswered));
  REQUIRE(line.peer_event("CALL_ESTABLISHED"));
  REQUIRE(peer.ua().command("hangup").ok);
  CHECK(marvin.wait_ended().end == CallEnd::kRemoteHungUp);
  REQUIRE(line.peer_event("CALL_CLOSED"));

  REQUIRE(peer.ua().command("dial", marvin.uri()).ok);
  REQUIRE(marvin.wait(Kind::kIncoming));
  CHECK(marvin.phone.decline());
  CHECK(marvin.wait_ended().end == CallEnd::kHungUp);
  const auto closed = line.peer_event("CALL_CLOSED");
  REQUIRE(closed);
  CHECK(closed->param.find("486") == 0);
}

TEST_CASE("a killed baresip is restarted and calls work again") {
  PhoneLine line(/*peer_answers=*/false);
  auto& peer = line.peer;
  auto& marvin = line.marvin;
  const pid_t first = marvin.phone.baresip().pid();
  REQUIRE(first > 0);
  REQUIRE(::kill(first, SIGKILL) == 0);
  REQUIRE(marvin.wait(Kind::kServiceRestarted));
  CHECK(marvin.phone.baresip().restarts() == 1);
  CHECK(marvin.phone.baresip().pid() != first);
  CHECK(marvin.phone.dial(peer.uri()) == "");
  CHECK(marvin.wait(Kind::kRinging));
}

TEST_CASE("a call in progress ends as failed when baresip dies") {
  PhoneLine line(/*peer_answers=*/false);
  auto& marvin = line.marvin;
  CHECK(marvin.phone.dial(line.peer.uri()) == "");
  REQUIRE(marvin.wait(Kind::kRinging));
  REQUIRE(::kill(marvin.phone.baresip().pid(), SIGKILL) == 0);
  const PhoneEvent ended = marvin.wait_ended();
  CHECK(ended.end == CallEnd::kFailed);
  CHECK(ended.reason == "the phone service stopped");
  CHECK(marvin.phone.state() == CallState::kIdle);
}

TEST_CASE("a refused registration is reported with the registrar's answer") {
  test_support::TempDir dir;
  // A registrar that is a plain user agent: it does not accept REGISTER.
  TestPeer registrar(dir / "registrar", /*auto_answer=*/false, "registrar");
  PhoneSettings settings = testing::marvin_settings(dir / "marvin");
  settings.registrar = "sip:127.0.0.1:" + std::to_string(registrar.ua().sip_port());
  settings.account_uri = "sip:marvin@127.0.0.1:" + std::to_string(registrar.ua().sip_port());
  settings.auth_user = "marvin";
  settings.auth_password = "secret";
  EventLog<PhoneEvent> events;
  Phone phone(settings, dir / "marvin" / "baresip", [&](const PhoneEvent& e) { events.add(e); });
  phone.start();
  std::size_t from = 0;
  const auto failed = events.wait(
      [](const PhoneEvent& e) {
        return e.kind == Kind::kRegistrationFailed || e.kind == Kind::kRegistered;
      },
      &from);
  REQUIRE(failed);
  CHECK(failed->kind == Kind::kRegistrationFailed);
  MESSAGE("registrar said: " << failed->reason);
  CHECK(failed->reason.find(settings.registrar + " refused the registration") == 0);
}

TEST_CASE("dialling something that is not a SIP address fails with baresip's words") {
  test_support::TempDir dir;
  MarvinPhone marvin(dir / "marvin");
  CHECK(marvin.phone.uri_for("0123 456 789") == "sip:0123456789@127.0.0.1:" +
                                                   std::to_string(marvin.phone.baresip().sip_port()));
  CHECK(marvin.phone.uri_for("sip:anna@example.org") == "sip:anna@example.org");
  CHECK(marvin.phone.uri_for("call anna") == "");
  CHECK(marvin.phone.uri_for("") == "");
}

TEST_CASE("malformed control socket input is logged and skipped; good events still arrive") {
  std::vector<std::string> logged;
  std::mutex log_mutex;
  auto previous = set_log_sink([&](LogLevel, std::string_view component, std::string_view text) {
    std::lock_guard lock(log_mutex);
    if (component == "phone") logged.emplace_back(text);
  });
  std::vector<BaresipEvent> events;
  {
    Baresip ua(PhoneSettings{}, "/nonexistent", [&](const BaresipEvent& e) { events.push_back(e); });
    ua.process_control_bytes("xyz");                          // no length
    ua.process_control_bytes("3:abcX");                       // no ','
    ua.process_control_bytes("5:hello,");                     // not JSON
    ua.process_control_bytes("2:[],");                        // not an object
    ua.process_control_bytes("14:{\"event\":true},");         // no type
    ua.process_control_bytes("21:{\"event\":\"yes\",\"a\":1},");  // event not a boolean
    ua.process_control_bytes("9999999:");                     // absurd length
    const std::string good =
        R"({"event":true,"type":"CALL_INCOMING","class":"call","peeruri":"sip:a@b","id":"1"})";
    const std::string frame = std::to_string(good.size()) + ":" + good + ",";
    ua.process_control_bytes(frame.substr(0, 10));  // split across reads
    ua.process_control_bytes(frame.substr(10));
  }
  set_log_sink(previous);
  REQUIRE(events.size() == 1);
  CHECK(events[0].type == "CALL_INCOMING");
  CHECK(events[0].peer_uri == "sip:a@b");
  std::string all;
  for (const auto& line : logged) all += line + "\n";
  CHECK(all.find("malformed netstring at byte 0: expected a length (digits), got 'x'") !=
        std::string::npos);
  CHECK(all.find("expected ',' after 3 bytes") != std::string::npos);
  CHECK(all.find("not a JSON object (ignored): hello") != std::string::npos);
  CHECK(all.find("not a JSON object (ignored): []") != std::string::npos);
  CHECK(all.find("event without a type") != std::string::npos);
  CHECK(all.find("neither an event nor a response") != std::string::npos);
  CHECK(all.find("length has more than 6 digits") != std::string::npos);
}

TEST_CASE("bad phone settings are refused naming the setting") {
  test_support::TempDir dir;
  PhoneSettings s;
  s.account_uri = "marvin@example.org";
  CHECK_THROWS_WITH(write_baresip_config(s, 5060, 4444, dir.path()),
                    doctest::Contains("account must be a SIP URI"));
  s.account_uri = "sip:marvin@example.org";
  s.registrar = "example.org";
  CHECK_THROWS_WITH(write_baresip_config(s, 5060, 4444, dir.path()),
                    doctest::Contains("registrar must be a SIP URI"));
  s.registrar = "";
  s.auth_password = "pw\nmodule evil.so";
  CHECK_THROWS_WITH(write_baresip_config(s, 5060, 4444, dir.path()),
                    doctest::Contains("password must not contain line breaks"));
  CHECK_FALSE(std::filesystem::exists(dir / "config"));
}

}  // namespace
}  // namespace marvin::telephony

namespace marvin::telephony {
namespace {

// Marvin's phone whose events go to the EmergencyCall under test, and the steps it says.
struct EmergencyLine {
  EmergencyLine(const std::filesystem::path& dir, std::chrono::milliseconds no_answer)
      : phone(testing::marvin_settings(dir), dir / "baresip",
              [this](const PhoneEvent& e) {
                std::lock_guard lock(mutex);
                if (call) call->on_phone_event(e);
              },
              no_answer) {
    phone.start();
    REQUIRE(phone.wait_ready(kWait));
  }
  ~EmergencyLine() {
    std::lock_guard lock(mutex);
    call.reset();
  }
  // Starts calling `contacts` for help.
  EmergencyCall& call_for_help(std::vector<EmergencyContact> contacts) {
    {
      std::lock_guard lock(mutex);
      call.emplace(phone, std::move(contacts),
                   [this](const std::string& text) { steps.add(text); });
    }
    call->start();
    return *call;
  }
  EventLog<std::string> steps;
  std::mutex mutex;
  std::optional<EmergencyCall> call;
  Phone phone;
};

TEST_CASE("call for help: busy, then no answer, then the third contact answers") {
  test_support::TempDir dir;
  TestPeer anna(dir / "anna", /*auto_answer=*/false, "anna");
  TestPeer ben(dir / "ben", /*auto_answer=*/false, "ben");
  TestPeer carla(dir / "carla", /*auto_answer=*/true, "carla");
  EmergencyLine line(dir / "marvin", std::chrono::milliseconds(800));
  EmergencyCall& call =
      line.call_for_help({{"Anna", anna.uri()}, {"Ben", ben.uri()}, {"Carla", carla.uri()}});
  std::size_t from = 0;
  REQUIRE(anna.wait_event("CALL_INCOMING", &from));
  REQUIRE(anna.ua().command("hangup").ok);  // Anna declines
  const auto answered = call.wait(kWait);
  REQUIRE(answered);
  CHECK(*answered == "Carla");
  CHECK(line.steps.all() == std::vector<std::string>{
                                "Calling Anna for help", "Anna did not answer (busy)",
                                "Calling Ben for help", "Ben did not answer (no answer)",
                                "Calling Carla for help", "Carla answered the emergency call"});
  CHECK(line.phone.state() == CallState::kInCall);
  CHECK(line.phone.peer() == carla.uri());
}

TEST_CASE("call for help: nobody answers, and that is said") {
  test_support::TempDir dir;
  TestPeer anna(dir / "anna", /*auto_answer=*/false, "anna");
  EmergencyLine line(dir / "marvin", std::chrono::milliseconds(500));
  EmergencyCall& call =
      line.call_for_help({{"Anna", anna.uri()}, {"Nobody", "sip:nobody@127.0.0.1:1"}});
  const auto answered = call.wait(kWait);
  REQUIRE(answered);
  CHECK(answered->empty());
  const auto all = line.steps.all();
  REQUIRE(all.size() == 5);
  CHECK(all[1] == "Anna did not answer (no answer)");
  CHECK(all[4] == "Nobody answered the emergency call");
}

}  // namespace
}  // namespace marvin::telephony
