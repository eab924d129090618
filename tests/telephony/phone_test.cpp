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
  std::string uri() { return phone.baresip().settings().account_uri; }
  EventLog<PhoneEvent> events;
  std::size_t seen = 0;
  Phone phone;
};

TEST_CASE("an answered call carries Marvin's tone to the other side and the other side's back") {
  test_support::TempDir dir;
  testing::write_tone_wav(dir / "tone.wav", 1000, 1.5);
  TestPeer peer(dir / "peer", /*auto_answer=*/true);  // sends ausine's 440 Hz
  MarvinPhone marvin(dir / "marvin", dir / "tone.wav");
  testing::ClosedFileWatch heard_files(peer.record_dir());
  testing::ClosedFileWatch marvin_heard_files(dir / "marvin" / "recordings");

  CHECK(marvin.phone.dial(peer.uri()) == "");
  REQUIRE(marvin.wait(Kind::kAnswered));
  CHECK(marvin.phone.state() == CallState::kInCall);
  CHECK(marvin.phone.peer() == peer.uri());
  // The tone file ends after 1.5 s, and with it the call (baresip 1.0's aufile).
  std::size_t from = 0;
  REQUIRE(peer.wait_event("CALL_CLOSED", &from));
  REQUIRE(marvin.wait(Kind::kEnded));
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
  test_support::TempDir dir;
  TestPeer peer(dir / "peer", /*auto_answer=*/false);
  MarvinPhone marvin(dir / "marvin");
  CHECK(marvin.phone.dial(peer.uri()) == "");
  std::size_t from = 0;
  REQUIRE(peer.wait_event("CALL_INCOMING", &from));
  REQUIRE(marvin.wait(Kind::kRinging));
  CHECK(marvin.phone.state() == CallState::kRinging);
  CHECK(marvin.phone.hang_up());
  const auto ended = marvin.wait(Kind::kEnded);
  REQUIRE(ended);
  CHECK(ended->end == CallEnd::kHungUp);
  CHECK(peer.wait_event("CALL_CLOSED", &from));
  CHECK(marvin.phone.state() == CallState::kIdle);
  CHECK_FALSE(marvin.phone.hang_up());  // nothing left to hang up
}

TEST_CASE("a declined call is reported busy") {
  test_support::TempDir dir;
  TestPeer peer(dir / "peer", /*auto_answer=*/false);
  MarvinPhone marvin(dir / "marvin");
  CHECK(marvin.phone.dial(peer.uri()) == "");
  std::size_t from = 0;
  REQUIRE(peer.wait_event("CALL_INCOMING", &from));
  CHECK(peer.ua().command("hangup").ok);
  const auto ended = marvin.wait(Kind::kEnded);
  REQUIRE(ended);
  CHECK(ended->end == CallEnd::kBusy);
  CHECK(ended->reason.find("486") == 0);
}

TEST_CASE("a call nobody answers ends as 'no answer' after the timeout") {
  test_support::TempDir dir;
  TestPeer peer(dir / "peer", /*auto_answer=*/false);
  MarvinPhone marvin(dir / "marvin", {}, std::chrono::milliseconds(800));
  CHECK(marvin.phone.dial(peer.uri()) == "");
  const auto ended = marvin.wait(Kind::kEnded);
  REQUIRE(ended);
  CHECK(ended->end == CallEnd::kNoAnswer);
  std::size_t from = 0;
  CHECK(peer.wait_event("CALL_CLOSED", &from));
}

TEST_CASE("an incoming call is announced, answered, then declined the next time") {
  test_support::TempDir dir;
  TestPeer peer(dir / "peer", /*auto_answer=*/false);
  MarvinPhone marvin(dir / "marvin");
  CHECK_FALSE(marvin.phone.answer());  // nothing rings yet
  REQUIRE(peer.ua().command("dial", marvin.uri()).ok);
  const auto incoming = marvin.wait(Kind::kIncoming);
  REQUIRE(incoming);
  CHECK(incoming->peer_uri == peer.uri());
  CHECK(marvin.phone.state() == CallState::kIncoming);
  CHECK(marvin.phone.answer());
  REQUIRE(marvin.wait(Kind::kAnswered));
  std::size_t from = 0;
  REQUIRE(peer.wait_event("CALL_ESTABLISHED", &from));
  REQUIRE(peer.ua().command("hangup").ok);
  const auto ended = marvin.wait(Kind::kEnded);
  REQUIRE(ended);
  CHECK(ended->end == CallEnd::kRemoteHungUp);
  REQUIRE(peer.wait_event("CALL_CLOSED", &from));

  REQUIRE(peer.ua().command("dial", marvin.uri()).ok);
  REQUIRE(marvin.wait(Kind::kIncoming));
  CHECK(marvin.phone.decline());
  const auto declined = marvin.wait(Kind::kEnded);
  REQUIRE(declined);
  CHECK(declined->end == CallEnd::kHungUp);
  const auto closed = peer.wait_event("CALL_CLOSED", &from);
  REQUIRE(closed);
  CHECK(closed->param.find("486") == 0);
}

TEST_CASE("a killed baresip is restarted and calls work again") {
  test_support::TempDir dir;
  TestPeer peer(dir / "peer", /*auto_answer=*/false);
  MarvinPhone marvin(dir / "marvin");
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
  test_support::TempDir dir;
  TestPeer peer(dir / "peer", /*auto_answer=*/false);
  MarvinPhone marvin(dir / "marvin");
  CHECK(marvin.phone.dial(peer.uri()) == "");
  REQUIRE(marvin.wait(Kind::kRinging));
  REQUIRE(::kill(marvin.phone.baresip().pid(), SIGKILL) == 0);
  const auto ended = marvin.wait(Kind::kEnded);
  REQUIRE(ended);
  CHECK(ended->end == CallEnd::kFailed);
  CHECK(ended->reason == "the phone service stopped");
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

TEST_CASE("call for help: busy, then no answer, then the third contact answers") {
  test_support::TempDir dir;
  TestPeer anna(dir / "anna", /*auto_answer=*/false, "anna");
  TestPeer ben(dir / "ben", /*auto_answer=*/false, "ben");
  TestPeer carla(dir / "carla", /*auto_answer=*/true, "carla");
  EventLog<std::string> steps;
  EmergencyCall* emergency = nullptr;
  std::mutex emergency_mutex;
  Phone phone(testing::marvin_settings(dir / "marvin"), dir / "marvin" / "baresip",
              [&](const PhoneEvent& e) {
                std::lock_guard lock(emergency_mutex);
                if (emergency) emergency->on_phone_event(e);
              },
              std::chrono::milliseconds(800));
  phone.start();
  REQUIRE(phone.wait_ready(kWait));
  {
    EmergencyCall call(phone,
                       {{"Anna", anna.uri()}, {"Ben", ben.uri()}, {"Carla", carla.uri()}},
                       [&](const std::string& text) { steps.add(text); });
    {
      std::lock_guard lock(emergency_mutex);
      emergency = &call;
    }
    call.start();
    std::size_t from = 0;
    REQUIRE(anna.wait_event("CALL_INCOMING", &from));
    REQUIRE(anna.ua().command("hangup").ok);  // Anna declines
    const auto answered = call.wait(kWait);
    REQUIRE(answered);
    CHECK(*answered == "Carla");
    CHECK(steps.all() == std::vector<std::string>{
                             "Calling Anna for help", "Anna did not answer (busy)",
                             "Calling Ben for help", "Ben did not answer (no answer)",
                             "Calling Carla for help", "Carla answered the emergency call"});
    CHECK(phone.state() == CallState::kInCall);
    CHECK(phone.peer() == carla.uri());
    std::lock_guard lock(emergency_mutex);
    emergency = nullptr;
  }
}

TEST_CASE("call for help: nobody answers, and that is said") {
  test_support::TempDir dir;
  TestPeer anna(dir / "anna", /*auto_answer=*/false, "anna");
  EventLog<std::string> steps;
  std::optional<EmergencyCall> call;
  std::mutex call_mutex;
  Phone phone(testing::marvin_settings(dir / "marvin"), dir / "marvin" / "baresip",
              [&](const PhoneEvent& e) {
                std::lock_guard lock(call_mutex);
                if (call) call->on_phone_event(e);
              },
              std::chrono::milliseconds(500));
  phone.start();
  REQUIRE(phone.wait_ready(kWait));
  {
    std::lock_guard lock(call_mutex);
    call.emplace(phone,
                 std::vector<EmergencyContact>{{"Anna", anna.uri()},
                                               {"Nobody", "sip:nobody@127.0.0.1:1"}},
                 [&](const std::string& text) { steps.add(text); });
  }
  call->start();
  const auto answered = call->wait(kWait);
  REQUIRE(answered);
  CHECK(answered->empty());
  const auto all = steps.all();
  REQUIRE(all.size() == 5);
  CHECK(all[1] == "Anna did not answer (no answer)");
  CHECK(all[4] == "Nobody answered the emergency call");
  std::lock_guard lock(call_mutex);
  call.reset();
}

}  // namespace
}  // namespace marvin::telephony
