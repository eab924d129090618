// `marvin phone call`: the real binary against a test peer on 127.0.0.1.
#include <doctest/doctest.h>

#include <cstdlib>

#include "support/child_process.h"
#include "support/files.h"
#include "telephony/call_fixture.h"

namespace marvin::telephony {
namespace {

std::string marvin_binary() {
  const char* build = std::getenv("MARVIN_BUILD_DIR");
  return std::string(build ? build : ".") + "/core/app/marvin";
}

std::vector<std::string> call_args(const test_support::TempDir& dir, const std::string& uri) {
  return {marvin_binary(), "phone", "call", uri, "--account",
          "sip:marvin@127.0.0.1:" + std::to_string(pick_free_port(true)), "--config-dir",
          (dir / "marvin").string()};
}

TEST_CASE("marvin phone call: answered, then 'hangup' on stdin ends it") {
  test_support::TempDir dir;
  testing::TestPeer peer(dir / "peer", /*auto_answer=*/true);
  test_support::ChildProcess marvin(call_args(dir, peer.uri()));
  marvin.wait_for_line("ringing " + peer.uri());
  marvin.wait_for_line("answered " + peer.uri());
  marvin.send_line("hangup");
  marvin.wait_for_line_containing("ended: hung up");
  CHECK(test_support::exit_code(marvin.finish()) == 0);
}

TEST_CASE("marvin phone call: a declined call is busy, exit code 2, and said so") {
  test_support::TempDir dir;
  testing::TestPeer peer(dir / "peer", /*auto_answer=*/false);
  test_support::ChildProcess marvin(call_args(dir, peer.uri()));
  std::size_t from = 0;
  REQUIRE(peer.wait_event("CALL_INCOMING", &from));
  REQUIRE(peer.ua().command("hangup").ok);
  marvin.wait_for_line("ended: busy (486 Rejected)");
  CHECK(test_support::exit_code(marvin.finish()) == 2);
  CHECK(marvin.errors().find("marvin: phone: the call was not answered") != std::string::npos);
}

TEST_CASE("marvin phone call: something that is not an address is refused by name") {
  test_support::TempDir dir;
  test_support::ChildProcess marvin(call_args(dir, "call anna"));
  CHECK(test_support::exit_code(marvin.finish()) == 1);
  CHECK(marvin.errors().find("phone: 'call anna' is neither a SIP address (sip:user@host) nor "
                             "a phone number") != std::string::npos);
}

}  // namespace
}  // namespace marvin::telephony
