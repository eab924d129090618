// A piped `marvin run --sim` session, checked line by line: the built-in time skill with
// a stopped clock, the example dice skill asking for a missing slot, no match, stop; and
// reminders kept in the SQLite store across runs and spoken by the scheduler. Every run
// gets $MARVIN_DATA_DIR in a temporary folder, so the real home directory is never used.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "support/child_process.h"

namespace fs = std::filesystem;
using marvin::test_support::ChildProcess;

namespace {

struct Result {
  int exit_code = -1;
  std::vector<std::string> lines;
  std::string errors;
  bool used_default_data_dir = false;
};

bool has_line(const Result& r, const std::string& line) {
  for (const auto& l : r.lines) {
    if (l == line) return true;
  }
  return false;
}

std::size_t count_containing(const Result& r, const std::string& text) {
  std::size_t n = 0;
  for (const auto& l : r.lines) {
    if (l.find(text) != std::string::npos) ++n;
  }
  return n;
}

// A data directory of its own for one test case.
struct TempDataDir {
  fs::path path = fs::temp_directory_path() /
                  ("marvin_sim_data_" + std::to_string(::getpid()) + "_" +
                   std::to_string(counter()++));
  TempDataDir() { fs::remove_all(path); }
  ~TempDataDir() { fs::remove_all(path); }
  static int& counter() {
    static int n = 0;
    return n;
  }
};

Result run_marvin(const std::string& arguments, const std::string& input) {
  fs::path dir = fs::temp_directory_path() / ("marvin_sim_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // The installed-skills default is loaded without --skills-dir: never the real one. The
  // arguments are shell words (quoted paths), so a shell runs the command line.
  marvin::test_support::ChildOptions options;
  options.environment = {"MARVIN_SKILLS_DIR=" + (dir / "no-installed-skills").string(),
                         "MARVIN_DATA_DIR=" + (dir / "default-data").string()};
  ChildProcess child = ChildProcess::shell(std::string("'") + MARVIN_EXE + "' " + arguments,
                                           options);
  child.write(input);
  Result result;
  result.exit_code = marvin::test_support::exit_code(child.finish());
  result.lines = child.output_lines();
  result.errors = child.errors();
  result.used_default_data_dir = fs::exists(dir / "default-data");
  fs::remove_all(dir);
  return result;
}

}  // namespace

TEST_CASE("a piped session: each answer in order, lights shown, clean exit at end of input") {
  Result r = run_marvin(std::string("run --sim --time-zone Europe/Berlin --clock 2026-11-21T15:05 "
                                    "--skills-dir '") +
                            EXAMPLES_DIR + "'",
                        "what time is it\n"
                        "What day is it?\n"
                        "roll some dice\n"
                        "two\n"
                        "paint me a picture\n"
                        "stop\n");
  CHECK(r.exit_code == 0);
  CHECK(r.errors == "");
  const std::vector<std::string> expected = {
      "[light: awaiting (red)]",
      "Marvin: Hello, I'm Marvin.",
      "You: what time is it",
      "[light: executing (yellow)]",
      "Marvin: It's 3:05 PM.",
      "[light: awaiting (red)]",
      "You: What day is it?",
      "[light: executing (yellow)]",
      "Marvin: Today is Saturday, 21 November 2026.",
      "[light: awaiting (red)]",
      "You: roll some dice",
      "Marvin: How many dice?",
      "You: two",
      "[light: executing (yellow)]",
      "(the roll)",
      "[light: awaiting (red)]",
      "You: paint me a picture",
      "(no match)",
      "You: stop",
      "Marvin: OK.",
  };
  REQUIRE(r.lines.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CAPTURE(i);
    if (expected[i] == "(no match)") {
      // The example names some installed skill's sentence.
      CHECK(std::regex_match(r.lines[i],
                             std::regex("Marvin: Sorry, I don't know how to help with "
                                        "that\\. You can ask me, for example: \"[a-z' ]+\"\\.")));
    } else if (expected[i] == "(the roll)") {
      CHECK(std::regex_match(r.lines[i],
                             std::regex("Marvin: You rolled [1-6] and [1-6]: [0-9]+ in total\\.")));
    } else {
      CHECK(r.lines[i] == expected[i]);
    }
  }
}

TEST_CASE("empty input: greets and exits cleanly") {
  Result r = run_marvin("run --sim --no-builtin-skills", "");
  CHECK(r.exit_code == 0);
  CHECK(r.lines ==
        std::vector<std::string>{"[light: awaiting (red)]", "Marvin: Hello, I'm Marvin."});
}

TEST_CASE("marvin skills list: skills, versions, kinds, intents and load errors") {
  Result r = run_marvin(std::string("skills list --skills-dir '") + EXAMPLES_DIR +
                            "' --skills-dir /nonexistent/skills",
                        "");
  CHECK(r.exit_code == 0);
  std::string all;
  for (const auto& line : r.lines) all += line + "\n";
  CHECK(all.find("time 1.0.0 (native) \"Time\" in ") != std::string::npos);
  CHECK(all.find("    intents: time, day, days_until\n") != std::string::npos);
  CHECK(all.find("dice 1.0.0 (native) \"Dice\" in ") != std::string::npos);
  CHECK(all.find("    intents: roll_one, roll_many, last_roll\n") != std::string::npos);
  CHECK(all.find("load errors:\n  skills directory /nonexistent/skills does not exist\n") !=
        std::string::npos);
}

TEST_CASE("marvin run without --sim says what to do when there is no sound card") {
  // Live mode opens the microphone first; a device no machine has stands for "no card".
  Result r = run_marvin("run --audio-device marvin-test-no-such-card", "");
  CHECK(r.exit_code == 1);
  CHECK(r.errors.rfind("marvin: no microphone: cannot open ALSA capture device "
                       "\"marvin-test-no-such-card\"", 0) == 0);
  CHECK(r.errors.find("`marvin run --sim`") != std::string::npos);
  CHECK(r.lines.empty());
}

TEST_CASE("without --data-dir the store is opened in $MARVIN_DATA_DIR") {
  Result r = run_marvin("run --sim --no-builtin-skills", "");
  CHECK(r.exit_code == 0);
  CHECK(r.used_default_data_dir);
  Result m = run_marvin("run --sim --no-builtin-skills --in-memory", "");
  CHECK(m.exit_code == 0);
  CHECK_FALSE(m.used_default_data_dir);
}

TEST_CASE("a reminder added by voice persists in the SQLite file and fires in a later run") {
  TempDataDir data;
  const std::string base = "run --sim --time-zone Europe/Berlin --data-dir '" +
                           data.path.string() + "' --clock ";

  Result add = run_marvin(base + "2026-11-21T15:05", "remind me to take my pills at 8 pm\n");
  CHECK(add.exit_code == 0);
  CHECK(has_line(add, "Marvin: OK, I'll remind you to take your pills today at 8 PM."));
  CHECK(fs::exists(data.path / "marvin.db"));
  CHECK_FALSE(add.used_default_data_dir);

  Result list = run_marvin(base + "2026-11-21T15:06", "what's on my schedule\n");
  CHECK(list.exit_code == 0);
  CHECK(has_line(list, "Marvin: Today: take your pills at 8 PM."));
  CHECK(count_containing(list, "Reminder") == 0);

  // Started at the due time, the scheduler says it once; the next start has nothing due.
  Result due = run_marvin(base + "2026-11-21T20:00", "");
  CHECK(due.exit_code == 0);
  CHECK(has_line(due, "Marvin: Reminder: take my pills"));
  Result after = run_marvin(base + "2026-11-21T20:01", "");
  CHECK(after.exit_code == 0);
  CHECK(count_containing(after, "take my pills") == 0);
}

TEST_CASE("a reminder due a while ago is announced as missed") {
  TempDataDir data;
  const std::string base = "run --sim --time-zone Europe/Berlin --data-dir '" +
                           data.path.string() + "' --clock ";
  Result add = run_marvin(base + "2026-11-21T15:05", "remind me to take my pills at 8 pm\n");
  CHECK(add.exit_code == 0);
  Result late = run_marvin(base + "2026-11-21T20:10", "");
  CHECK(late.exit_code == 0);
  CHECK(has_line(late, "Marvin: You missed a reminder: take my pills"));
}

TEST_CASE("a store that cannot be opened is a clear error and stays as it was") {
  TempDataDir data;
  fs::create_directories(data.path);
  const std::string garbage = "this is not an SQLite database, just text of some length....";
  std::ofstream(data.path / "marvin.db") << garbage;
  Result r = run_marvin("run --sim --no-builtin-skills --data-dir '" + data.path.string() + "'",
                        "");
  CHECK(r.exit_code == 1);
  CHECK(r.errors.find("marvin: cannot open the personal data: ") == 0);
  CHECK(r.errors.find((data.path / "marvin.db").string()) != std::string::npos);
  std::ifstream in(data.path / "marvin.db");
  std::string after((std::istreambuf_iterator<char>(in)), {});
  CHECK(after == garbage);

  Result list = run_marvin("skills list --data-dir '" + data.path.string() + "'", "");
  CHECK(list.exit_code == 1);
}

#ifdef LUA_FIXTURES_DIR
TEST_CASE("Lua marvin.after timers fire on the host loop, in order, on the host clock") {
  Result r = run_marvin(std::string("run --sim --in-memory --no-builtin-skills --clock "
                                    "2026-11-21T15:05 --time-zone UTC --skills-dir '") +
                            LUA_FIXTURES_DIR + "'",
                        "ring in an hour\nring now\nring now\n");
  CHECK(r.exit_code == 0);
  std::vector<std::string> spoken;
  for (const auto& line : r.lines) {
    if (line.rfind("Marvin: ", 0) == 0 || line.rfind("You: ", 0) == 0) spoken.push_back(line);
  }
  // The clock is stopped: the hour never passes; a timer due now fires before the next
  // utterance is taken, and at end of input.
  CHECK(spoken == std::vector<std::string>{"Marvin: Hello, I'm Marvin.",
                                           "You: ring in an hour",
                                           "Marvin: Ringing in an hour.",
                                           "You: ring now",
                                           "Marvin: Ringing soon.",
                                           "Marvin: Ring!",
                                           "You: ring now",
                                           "Marvin: Ringing soon.",
                                           "Marvin: Ring!"});
}
#endif

TEST_CASE("--in-memory keeps no faces: learning one says so, not that the camera is broken") {
  // The simulated camera works ("what do you see" answers from the world); only the store
  // that keeps faces and things is missing.
  // The robot first comes to the user: a face is asked about only when one is in view.
  Result r = run_marvin("run --sim --in-memory",
                        "come here\nthis is my daughter\nyes\nthese are my keys\n");
  CHECK(r.exit_code == 0);
  CHECK(has_line(r, "Marvin: Shall I remember this face as Anna?"));  // the contact book's daughter
  CHECK(count_containing(r, "I can't learn anything new right now: I have nowhere to keep it.") == 2);
  CHECK(count_containing(r, "camera is not working") == 0);
}
