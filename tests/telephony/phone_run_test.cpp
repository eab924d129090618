// End to end: `marvin run --sim` with its phone (a real baresip) and typed requests; the
// other ends are the simulated one (examples/worlds/phone.json, auto-answering) and test
// peers on 127.0.0.1 that decline, never answer, or call Marvin. Each step waits for a line
// of the transcript or a peer's event (generous timeouts, only reached on failure).
#include <doctest/doctest.h>
#include <dirent.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/child_process.h"
#include "support/files.h"
#include "telephony/call_fixture.h"

namespace marvin::telephony {
namespace {

using test_support::ChildProcess;

std::string marvin_exe() {
  const char* build = std::getenv("MARVIN_BUILD_DIR");
  return std::string(build ? build : ".") + "/core/app/marvin";
}

// `marvin contacts add` into `data`.
void add_contact(const test_support::TempDir& data, std::vector<std::string> args) {
  std::vector<std::string> argv{marvin_exe(), "contacts", "add"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--data-dir", data.path().string()});
  test_support::ChildOptions o;
  o.in = test_support::ChildStream::kNull;
  ChildProcess add(argv, o);
  REQUIRE(test_support::exit_code(add.finish()) == 0);
}

struct Marvin {
  int port = pick_free_port(true);
  ChildProcess process;
  Marvin(const test_support::TempDir& data, std::vector<std::string> extra = {},
         std::vector<std::string> environment = {})
      : process(
            [&] {
              std::vector<std::string> argv{marvin_exe(), "run", "--sim", "--data-dir",
                                            data.path().string(), "--phone-port",
                                            std::to_string(port), "--phone-no-answer", "2"};
              argv.insert(argv.end(), extra.begin(), extra.end());
              return argv;
            }(),
            [&] {
              test_support::ChildOptions o;
              // No installed skills of the machine: the built-in ones only.
              o.environment = {"MARVIN_SKILLS_DIR=/nonexistent/marvin-phone-test"};
              o.environment.insert(o.environment.end(), environment.begin(), environment.end());
              return o;
            }()) {
    process.wait_for_line("Marvin: Hello, I'm Marvin.");
  }
  void say(const std::string& line) { process.send_line(line); }
  void expect(const std::string& line) { process.wait_for_line("Marvin: " + line); }
  std::string uri() const { return "sip:marvin@127.0.0.1:" + std::to_string(port); }
};

// The baresip children of `parent` (by /proc), Marvin's own one being the one whose
// configuration directory ends in "/marvin".
pid_t marvin_baresip(pid_t parent) {
  DIR* proc = ::opendir("/proc");
  REQUIRE(proc != nullptr);
  pid_t found = -1;
  while (dirent* entry = ::readdir(proc)) {
    const std::string name = entry->d_name;
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat("/proc/" + name + "/stat");
    std::string pid, comm, state;
    pid_t ppid = 0;
    stat >> pid >> comm >> state >> ppid;
    if (ppid != parent || comm != "(baresip)") continue;
    std::ifstream cmdline("/proc/" + name + "/cmdline");
    std::string args((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    for (char& c : args) c = c == '\0' ? ' ' : c;
    if (args.find("/marvin ") != std::string::npos || args.ends_with("/marvin ")) {
      found = static_cast<pid_t>(std::stol(name));
    }
  }
  ::closedir(proc);
  return found;
}

nlohmann::json exported_events(const test_support::TempDir& data) {
  const std::string file = (data / "export.json").string();
  test_support::ChildOptions o;
  o.in = test_support::ChildStream::kNull;
  ChildProcess exporter({marvin_exe(), "data", "export", file, "--data-dir",
                         data.path().string()},
                        o);
  REQUIRE(test_support::exit_code(exporter.finish()) == 0);
  std::ifstream in(file);
  return nlohmann::json::parse(in)["events"];
}

TEST_CASE("run --sim: call my daughter, progress said, connected; hang up by voice") {
  test_support::TempDir data;
  Marvin m(data);
  m.say("call my daughter");
  m.expect("Call Anna?");
  m.say("yes");
  m.expect("Ringing Anna.");
  m.expect("You're connected to Anna.");
  m.say("hang up");
  m.expect("OK, I hung up. The call with Anna has ended.");
  m.say("hang up");
  m.expect("There is no call to hang up.");
  // Doctor Brown's number, said aloud: the simulated Doctor Brown answers on it.
  m.say("call 0123 456 789");
  m.expect("Call Doctor Brown on 0123 456 789?");
  m.say("yes");
  m.expect("You're connected to Doctor Brown.");
  // "stop" during a call hangs up too. Said right after "connected", it may still find
  // the call request finishing ("OK, I stopped."): the call ends either way.
  m.say("stop");
  m.process.wait_for_line("the answer to stop", [](const std::string& line) {
    return line == "Marvin: OK, I hung up." || line == "Marvin: OK, I stopped.";
  });
  m.say("hang up");
  m.expect("There is no call to hang up.");
  m.say("stop");
  m.expect("OK.");
  CHECK(test_support::exit_code(m.process.finish()) == 0);
}

TEST_CASE("run --sim: busy and not answering are said; unknown people and no number too") {
  test_support::TempDir dir;
  test_support::TempDir data;
  testing::TestPeer bob(dir / "bob", /*auto_answer=*/false, "bob");
  testing::TestPeer carl(dir / "carl", /*auto_answer=*/false, "carl");
  add_contact(data, {"Bob", "--sip", bob.uri(), "--relation", "brother"});
  add_contact(data, {"Carl", "--sip", carl.uri()});
  add_contact(data, {"Eve", "--relation", "niece"});
  Marvin m(data);
  m.say("call my brother");
  m.expect("Call Bob?");
  m.say("yes");
  std::size_t from = 0;
  REQUIRE(bob.wait_event("CALL_INCOMING", &from));
  REQUIRE(bob.ua().command("hangup").ok);  // declines: 486
  m.expect("The line is busy. Bob can't take the call now.");
  m.say("phone Carl");
  m.expect("Call Carl?");
  m.say("yes");
  m.expect("Ringing Carl.");
  m.expect("Carl is not answering.");  // --phone-no-answer 2
  from = 0;
  CHECK(carl.wait_event("CALL_CLOSED", &from));
  m.say("call my niece");
  m.expect("I have no number for Eve.");
  m.say("call Zorro");
  m.expect("I don't know anyone called zorro.");
  CHECK(test_support::exit_code(m.process.finish()) == 0);
}

TEST_CASE("run --sim: an incoming call is announced, answered by voice, then declined") {
  test_support::TempDir dir;
  test_support::TempDir data;
  testing::TestPeer bob(dir / "bob", /*auto_answer=*/false, "bob");
  add_contact(data, {"Bob", "--sip", bob.uri()});
  Marvin m(data);
  REQUIRE(bob.ua().command("dial", m.uri()).ok);
  m.expect("Bob is calling. Say answer or decline.");
  m.say("answer");
  m.expect("You're connected to Bob.");
  std::size_t from = 0;
  REQUIRE(bob.wait_event("CALL_ESTABLISHED", &from));
  REQUIRE(bob.ua().command("hangup").ok);
  m.expect("Bob hung up.");
  REQUIRE(bob.ua().command("dial", m.uri()).ok);
  m.expect("Bob is calling. Say answer or decline.");
  m.say("decline");
  m.expect("I declined the call from Bob.");
  CHECK(bob.wait_event("CALL_CLOSED", &from));
  const int status = m.process.finish();
  INFO("signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << "; stderr:\n"
                 << m.process.errors() << "\nstdout:\n" << m.process.output());
  CHECK(test_support::exit_code(status) == 0);
}

TEST_CASE("run --sim: call for help goes on past a busy contact; every step is logged") {
  test_support::TempDir dir;
  test_support::TempDir data;
  // Anna exists already (so the simulated one is not added) and declines; Doctor Brown
  // (the simulated one, emergency contact 2) answers.
  testing::TestPeer anna(dir / "anna", /*auto_answer=*/false, "anna");
  add_contact(data, {"Anna", "--sip", anna.uri(), "--emergency", "1"});
  Marvin m(data);
  m.say("call for help");
  m.expect("Calling Anna for help.");
  std::size_t from = 0;
  REQUIRE(anna.wait_event("CALL_INCOMING", &from));
  REQUIRE(anna.ua().command("hangup").ok);
  m.expect("Anna did not answer (busy).");
  m.expect("Calling Doctor Brown for help.");
  m.expect("Doctor Brown answered the emergency call.");
  m.expect("You're connected to Doctor Brown.");
  m.say("hang up");
  m.expect("OK, I hung up. The call with Doctor Brown has ended.");
  CHECK(test_support::exit_code(m.process.finish()) == 0);
  std::vector<std::string> logged;
  for (const auto& e : exported_events(data)) {
    if (e["kind"] == "emergency") logged.push_back(e["message"]);
  }
  CHECK(logged == std::vector<std::string>{"Calling Anna for help", "Anna did not answer (busy)",
                                           "Calling Doctor Brown for help",
                                           "Doctor Brown answered the emergency call"});
}

TEST_CASE("run --sim: call for help during a call ends that call first") {
  test_support::TempDir data;
  Marvin m(data);
  m.say("phone Tom");
  m.expect("Call Tom?");
  m.say("yes");
  m.expect("You're connected to Tom.");
  m.say("help me");
  m.expect("Calling Anna for help.");
  m.expect("Anna answered the emergency call.");
  m.expect("You're connected to Anna.");
  m.say("hang up");
  m.expect("OK, I hung up. The call with Anna has ended.");
  CHECK(test_support::exit_code(m.process.finish()) == 0);
}

TEST_CASE("run --sim: a killed baresip is restarted and the next call works") {
  test_support::TempDir data;
  Marvin m(data);
  const pid_t first = marvin_baresip(m.process.pid());
  REQUIRE(first > 0);
  REQUIRE(::kill(first, SIGKILL) == 0);
  // The dial waits for the restarted baresip's control socket (no sleep here).
  m.say("call Annie");
  m.expect("Call Anna?");
  m.say("yes");
  m.expect("You're connected to Anna.");
  const pid_t second = marvin_baresip(m.process.pid());
  CHECK(second > 0);
  CHECK(second != first);
  m.say("hang up");
  m.expect("OK, I hung up. The call with Anna has ended.");
  CHECK(test_support::exit_code(m.process.finish()) == 0);
}

// The baresip children of `parent`, whatever their configuration (Marvin's and the
// simulated phone's).
std::vector<pid_t> baresip_children(pid_t parent) {
  std::vector<pid_t> found;
  DIR* proc = ::opendir("/proc");
  REQUIRE(proc != nullptr);
  while (dirent* entry = ::readdir(proc)) {
    const std::string name = entry->d_name;
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat("/proc/" + name + "/stat");
    std::string pid, comm, state;
    pid_t ppid = 0;
    stat >> pid >> comm >> state >> ppid;
    if (ppid == parent && comm == "(baresip)") found.push_back(static_cast<pid_t>(std::stol(name)));
  }
  ::closedir(proc);
  return found;
}

// True when `pid` has ended within `timeout` (waits on a pidfd: no polling by sleep).
bool process_ends(pid_t pid, std::chrono::milliseconds timeout) {
  const int fd = static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
  if (fd < 0) return errno == ESRCH;  // already gone
  pollfd p{fd, POLLIN, 0};
  const bool ended = ::poll(&p, 1, static_cast<int>(timeout.count())) == 1;
  ::close(fd);
  return ended;
}

TEST_CASE("run --sim killed with SIGKILL: its baresip children end with it") {
  test_support::TempDir data;
  Marvin m(data);
  const std::vector<pid_t> children = baresip_children(m.process.pid());
  REQUIRE(children.size() >= 1);
  REQUIRE(marvin_baresip(m.process.pid()) > 0);
  m.process.stop(SIGKILL);
  for (pid_t child : children) {
    CAPTURE(child);
    CHECK(process_ends(child, testing::kWait));
  }
}

TEST_CASE("run --sim --phone-config: a refused registration is said, and calls say why not") {
  test_support::TempDir dir;
  test_support::TempDir data;
  // A registrar that is a plain user agent: it does not accept REGISTER.
  testing::TestPeer registrar(dir / "registrar", /*auto_answer=*/false, "registrar");
  const std::string at = "127.0.0.1:" + std::to_string(registrar.ua().sip_port());
  test_support::write_text(dir / "phone.json",
                           R"({"account": "sip:marvin@)" + at + R"(", "registrar": "sip:)" + at +
                               R"(", "user": "marvin", "password": "secret"})");
  Marvin m(data, {"--phone-config", (dir / "phone.json").string()});
  // The registrar answers within milliseconds, so the refusal races the greeting: it may be
  // among the lines the wait for the greeting went past. (Waiting for the next one would
  // wait for baresip to try again, about a minute later.)
  const auto refusal = [](const std::string& line) {
    return line.rfind("Marvin: I can't make phone calls: sip:", 0) == 0;
  };
  std::string said;
  for (const std::string& line : m.process.output_lines()) {
    if (said.empty() && refusal(line)) said = line;
  }
  if (said.empty()) said = m.process.wait_for_line("the refusal", refusal);
  CHECK(said.find("refused the registration") != std::string::npos);
  m.say("call my daughter");
  m.expect("Call Anna?");
  m.say("yes");
  const std::string why = m.process.wait_for_line(
      "the call refused", [](const std::string& line) {
        return line.rfind("Marvin: I can't make the call: sip:", 0) == 0;
      });
  CHECK(why.find("refused the registration") != std::string::npos);
  CHECK(test_support::exit_code(m.process.finish()) == 0);
}

TEST_CASE("run --phone-config: a malformed configuration names the file and the field") {
  test_support::TempDir dir;
  test_support::TempDir data;
  test_support::write_text(dir / "phone.json", R"({"account": "robot@example.org"})");
  test_support::ChildOptions o;
  o.in = test_support::ChildStream::kNull;
  ChildProcess run({marvin_exe(), "run", "--sim", "--data-dir", data.path().string(),
                    "--phone-config", (dir / "phone.json").string()},
                   o);
  CHECK(test_support::exit_code(run.finish()) == 2);
  CHECK(run.errors().find("--phone-config: " + (dir / "phone.json").string() +
                          ": account: expected a SIP address like sip:robot@sip.example.org, "
                          "got \"robot@example.org\"") != std::string::npos);
  test_support::write_text(dir / "phone.json", R"({"account": "sip:r@x", "sip_port": "5060"})");
  ChildProcess again({marvin_exe(), "run", "--sim", "--data-dir", data.path().string(),
                      "--phone-config", (dir / "phone.json").string()},
                     o);
  CHECK(test_support::exit_code(again.finish()) == 2);
  CHECK(again.errors().find("sip_port: expected a port number 0..65534 (0: a free one), got "
                            "\"5060\"") != std::string::npos);
}

TEST_CASE("run --sim --no-phone: calls are refused in words") {
  test_support::TempDir data;
  Marvin m(data, {"--no-phone"});
  m.say("call my daughter");
  m.expect("I can't make the call: this robot has no telephone.");
  CHECK(test_support::exit_code(m.process.finish()) == 0);
}

// SIGTERM (systemd stopping the service, a `kill`) is a clean stop, not a death: the call
// ends, baresip goes, and the phone's files in the temporary directory go with it. The
// input stays open: the signal alone ends Marvin.
TEST_CASE("run --sim stopped with SIGTERM during a call: baresip ends, its files go, exit 0") {
  test_support::TempDir data;
  test_support::TempDir tmp;
  Marvin m(data, {}, {"TMPDIR=" + tmp.path().string()});
  m.say("call my daughter");
  m.expect("Call Anna?");
  m.say("yes");
  m.expect("You're connected to Anna.");
  const std::vector<pid_t> children = baresip_children(m.process.pid());
  REQUIRE(children.size() == 2);
  bool phone_files = false;
  for (const auto& e : std::filesystem::directory_iterator(tmp.path())) {
    phone_files = phone_files || e.path().filename().string().rfind("marvin-phone-", 0) == 0;
  }
  REQUIRE(phone_files);
  REQUIRE(::kill(m.process.pid(), SIGTERM) == 0);
  // The output ends when Marvin exits; stdin is still open.
  CHECK_FALSE(m.process.read_until([](const std::string&) { return false; }));
  CHECK(test_support::exit_code(m.process.finish()) == 0);
  CHECK(m.process.output().find("[SIGTERM: stopping]") != std::string::npos);
  for (pid_t child : children) {
    CAPTURE(child);
    CHECK(process_ends(child, testing::kWait));
  }
  CHECK(std::filesystem::is_empty(tmp.path()));
}

}  // namespace
}  // namespace marvin::telephony
