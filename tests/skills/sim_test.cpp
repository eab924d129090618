// A piped `marvin run --sim` session, checked line by line: the built-in time skill with
// a stopped clock, the example dice skill asking for a missing slot, no match, stop.
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code = -1;
  std::vector<std::string> lines;
  std::string errors;
};

Result run_marvin(const std::string& arguments, const std::string& input) {
  fs::path dir = fs::temp_directory_path() / ("marvin_sim_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "input.txt") << input;
  std::string command = std::string("'") + MARVIN_EXE + "' " + arguments + " < '" +
                        (dir / "input.txt").string() + "' 2> '" + (dir / "stderr.txt").string() +
                        "'";
  Result result;
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string output;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) result.lines.push_back(line);
  std::ifstream err(dir / "stderr.txt");
  result.errors.assign(std::istreambuf_iterator<char>(err), {});
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
                        "sing me a song\n"
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
      "You: sing me a song",
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
  CHECK(all.find("    intents: time, day\n") != std::string::npos);
  CHECK(all.find("dice 1.0.0 (native) \"Dice\" in ") != std::string::npos);
  CHECK(all.find("    intents: roll_one, roll_many, last_roll\n") != std::string::npos);
  CHECK(all.find("load errors:\n  skills directory /nonexistent/skills does not exist\n") !=
        std::string::npos);
}

TEST_CASE("marvin run without --sim says what to do") {
  Result r = run_marvin("run", "");
  CHECK(r.exit_code == 2);
  CHECK(r.errors ==
        "marvin: only the simulated robot is available in this build: use `marvin run --sim`\n");
}
