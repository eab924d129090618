// ChildProcess (child_process.h) on real processes: /bin/sh, cat, env. Every wait is on the
// child's output or exit; nothing asserts on time.
#include "support/child_process.h"

#include <doctest/doctest.h>
#include <signal.h>

#include <cerrno>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/files.h"

using marvin::test_support::ChildOptions;
using marvin::test_support::ChildProcess;
using marvin::test_support::ChildStream;
using marvin::test_support::exit_code;

TEST_CASE("arguments and environment in, stdout and stderr out, the exit code at the end") {
  ChildOptions options;
  options.environment = {"MARVIN_CHILD_TEST=from the test"};
  ChildProcess child({"/bin/sh", "-c", "echo \"$MARVIN_CHILD_TEST $1\"; echo oops >&2; exit 3",
                      "sh", "and an argument"},
                     options);
  CHECK(exit_code(child.finish()) == 3);
  CHECK(child.output() == "from the test and an argument\n");
  CHECK(child.errors() == "oops\n");
  CHECK(child.output_lines() == std::vector<std::string>{"from the test and an argument"});
}

TEST_CASE("a clean environment holds only what the test gives") {
  ChildOptions options;
  options.environment = {"ONLY=this"};
  options.clean_environment = true;
  ChildProcess child({"/usr/bin/env"}, options);
  CHECK(exit_code(child.finish()) == 0);
  CHECK(child.output() == "ONLY=this\n");
}

TEST_CASE("a conversation: lines written to stdin come back, waited for line by line") {
  ChildProcess cat({"/bin/cat"});
  cat.send_line("first");
  CHECK(cat.wait_for_line("first") == "first");
  cat.send_line("second line");
  cat.send_line("third");
  CHECK(cat.wait_for_line_containing("cond") == "second line");
  CHECK(cat.wait_for_line("a line of five letters",
                          [](const std::string& l) { return l.size() == 5; }) == "third");
  CHECK(exit_code(cat.finish()) == 0);
  CHECK(cat.output_lines() == std::vector<std::string>{"first", "second line", "third"});
}

TEST_CASE("input larger than a pipe holds is written while the output is read") {
  const std::string big(1 << 20, 'x');
  ChildProcess cat({"/bin/cat"});
  cat.write(big);
  CHECK(exit_code(cat.finish()) == 0);
  CHECK(cat.output() == big);
}

TEST_CASE("a line that never comes: the error names it and shows the output so far") {
  ChildProcess child = ChildProcess::shell("echo one; echo two");
  try {
    child.wait_for_line("three");
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    CHECK(message.find("no line \"three\" before the output ended") != std::string::npos);
    CHECK(message.find("one\ntwo\n") != std::string::npos);
  }
  CHECK(exit_code(child.finish()) == 0);
}

TEST_CASE("read_until: true once the output holds the text, false when the output ends") {
  ChildProcess child = ChildProcess::shell("printf 'no newline: '; read answer; echo \"$answer!\"");
  CHECK(child.read_until(
      [](const std::string& out) { return out.find("no newline: ") != std::string::npos; }));
  child.send_line("yes");
  CHECK(child.read_until([](const std::string& out) { return out.ends_with("yes!\n"); }));
  CHECK_FALSE(child.read_until([](const std::string& out) { return out.find("never") != std::string::npos; }));
  CHECK(exit_code(child.finish()) == 0);
}

TEST_CASE("a child ended by a signal has no exit code; stop() sends the signal and reaps") {
  ChildOptions options;
  options.in = ChildStream::kPipe;  // cat waits on it, so it runs until stopped
  ChildProcess cat({"/bin/cat"}, options);
  const pid_t pid = cat.pid();
  cat.stop(SIGTERM);
  CHECK(cat.pid() == -1);
  CHECK(::kill(pid, 0) == -1);  // reaped: the pid is gone
  CHECK(errno == ESRCH);
  cat.stop(SIGKILL);  // no effect once reaped

  ChildProcess self_killed = ChildProcess::shell("kill -9 $$");
  CHECK(exit_code(self_killed.finish()) == -1);
}

TEST_CASE("a child still running when the object goes is killed and reaped") {
  pid_t pid = -1;
  {
    ChildProcess cat({"/bin/cat"});
    pid = cat.pid();
    cat.send_line("alive");
    cat.wait_for_line("alive");
    CHECK(::kill(pid, 0) == 0);
  }
  CHECK(::kill(pid, 0) == -1);
  CHECK(errno == ESRCH);
}

TEST_CASE("stderr to a file; stdin and stdout from and to /dev/null") {
  marvin::test_support::TempDir dir;
  ChildOptions options;
  options.in = ChildStream::kNull;
  options.out = ChildStream::kNull;
  options.err_file = dir / "err.txt";
  ChildProcess child = ChildProcess::shell("cat; echo to-stdout; echo to-stderr >&2", options);
  CHECK(exit_code(child.finish()) == 0);
  CHECK(child.output().empty());
  CHECK(child.errors().empty());
  CHECK(marvin::test_support::read_text(dir / "err.txt") == "to-stderr\n");
}

TEST_CASE("on a terminal: the child sees a tty, prompts without a newline, reads the answer") {
  ChildOptions options;
  options.terminal = true;
  ChildProcess child = ChildProcess::shell(
      "if [ -t 0 ] && [ -t 1 ]; then printf 'Approve? [y/N] '; read a; echo \"got $a\"; fi",
      options);
  REQUIRE(child.read_until(
      [](const std::string& out) { return out.find("Approve? [y/N] ") != std::string::npos; }));
  child.write("y\n");
  CHECK(exit_code(child.finish()) == 0);
  CHECK(child.output().find("got y") != std::string::npos);
}

TEST_CASE("a program that does not exist exits 127; an empty argv is refused") {
  ChildProcess missing({"/nonexistent/marvin-test-program"});
  CHECK(exit_code(missing.finish()) == 127);
  CHECK_THROWS_WITH_AS(ChildProcess(std::vector<std::string>{}),
                       "ChildProcess: argv is empty (expected a program)", std::runtime_error);
}
