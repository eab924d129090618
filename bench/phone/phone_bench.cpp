// Prints two figures for issue 20's goals, measured between two real baresip user agents
// on 127.0.0.1 (Marvin's Phone and a test peer that never answers):
//  - request -> ringing at the other end: from Phone::dial() to the peer's CALL_INCOMING
//    event (median, p90 over N calls); baseline in the same run: the ctrl_tcp round trip of
//    a no-op command, the floor under any request;
//  - supervision: SIGKILL of Marvin's baresip -> the phone ready again (median over M kills).
// Never fails on time. Usage: bench_phone [calls=20] [kills=5]
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/log.h"
#include "support/files.h"
#include "telephony/call_fixture.h"

using namespace marvin::telephony;
using Clock = std::chrono::steady_clock;

namespace {

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  const int calls = argc > 1 ? std::atoi(argv[1]) : 20;
  const int kills = argc > 2 ? std::atoi(argv[2]) : 5;
  marvin::set_log_level(marvin::LogLevel::kWarning);
  marvin::test_support::TempDir dir;
  testing::TestPeer peer(dir / "peer", /*auto_answer=*/false);
  testing::EventLog<PhoneEvent> events;
  Phone phone(testing::marvin_settings(dir / "marvin"), dir / "marvin" / "baresip",
              [&](const PhoneEvent& e) { events.add(e); });
  phone.start();
  if (!phone.wait_ready(testing::kWait)) {
    std::fprintf(stderr, "bench_phone: baresip did not start\n");
    return 1;
  }
  std::size_t peer_seen = 0, seen = 0;
  std::vector<double> ringing, round_trip;
  for (int i = 0; i < calls; ++i) {
    auto t0 = Clock::now();
    phone.baresip().command("reginfo");
    round_trip.push_back(ms(Clock::now() - t0));
    t0 = Clock::now();
    if (!phone.dial(peer.uri()).empty()) return 1;
    if (!peer.wait_event("CALL_INCOMING", &peer_seen)) return 1;
    ringing.push_back(ms(Clock::now() - t0));
    phone.hang_up();
    if (!events.wait([](const PhoneEvent& e) { return e.kind == PhoneEvent::Kind::kEnded; },
                     &seen)) {
      return 1;
    }
    if (!peer.wait_event("CALL_CLOSED", &peer_seen)) return 1;
  }
  std::printf("request -> ringing at the other end (%d calls): median %.1f ms, p90 %.1f ms "
              "(goal < 1000 ms)\n", calls, percentile(ringing, 0.5), percentile(ringing, 0.9));
  std::printf("baseline, ctrl_tcp command round trip: median %.2f ms; ringing/round trip = %.1fx\n",
              percentile(round_trip, 0.5), percentile(ringing, 0.5) / percentile(round_trip, 0.5));
  std::vector<double> restart;
  for (int i = 0; i < kills; ++i) {
    const auto t0 = Clock::now();
    ::kill(phone.baresip().pid(), SIGKILL);
    if (!events.wait(
            [](const PhoneEvent& e) { return e.kind == PhoneEvent::Kind::kServiceRestarted; },
            &seen)) {
      return 1;
    }
    restart.push_back(ms(Clock::now() - t0));
  }
  std::printf("killed baresip -> phone ready again (%d kills): median %.1f ms, max %.1f ms "
              "(goal < 2000 ms)\n", kills, percentile(restart, 0.5), percentile(restart, 1.0));
  return 0;
}
