// The voice loop inside the real skill host, end to end: `marvin run --sim --audio-in X.wav
// --audio-out Y.wav` on recordings made by espeak-ng during the test (no committed audio),
// with the built-in skills, in-memory personal data and a stopped clock. Checked: the
// transcript (what was heard, what Marvin said), the status light's order, and the output
// WAV, which is aligned with the input: silence while the user speaks, speech where Marvin
// answers, cut short where "Marvin, stop" was said.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "devices/audio/sound_file.h"
#include "speech_fixture.h"
#include "support/child_process.h"
#include "web_client.h"

namespace fs = std::filesystem;
using namespace marvin::perception::testing;

namespace {

constexpr int kRate = 16000;

struct Result {
  int exit_code = -1;
  std::vector<std::string> lines;
  std::string errors;
  std::vector<std::int16_t> output;  // the --audio-out file, when written
};

// A recording under construction; remembers where each piece of speech starts and ends.
struct Recording {
  std::vector<std::int16_t> audio;
  struct Piece {
    std::size_t begin = 0;  // first sample of the piece (its leading silence included)
    std::size_t speech_end = 0;  // last loud sample + 1
  };
  std::vector<Piece> pieces;

  Recording& silence(int ms) {
    audio.resize(audio.size() + static_cast<std::size_t>(ms) * 16, 0);
    return *this;
  }
  Recording& say(const std::string& text, int before_ms = 300, int after_ms = 2500) {
    const std::vector<std::int16_t> u = utterance(text, before_ms, after_ms);
    Piece p;
    p.begin = audio.size();
    std::size_t last = 0;
    for (std::size_t i = 0; i < u.size(); ++i) {
      if (std::abs(u[i]) > 300) last = i + 1;
    }
    p.speech_end = audio.size() + last;
    audio.insert(audio.end(), u.begin(), u.end());
    pieces.push_back(p);
    return *this;
  }
};

// One folder for the whole run (each case rewrites its files), removed at exit.
struct TempDir {
  fs::path path = fs::temp_directory_path() /
                  ("marvin_voice_host_test_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

fs::path temp_dir() {
  static const TempDir dir;
  return dir.path;
}

Result run_marvin(const std::string& arguments, const Recording* input = nullptr) {
  const fs::path dir = temp_dir();
  const fs::path in = dir / "in.wav", out = dir / "out.wav";
  fs::remove(out);
  // The arguments are shell words, so a shell runs the command line.
  std::string command = std::string("'") + MARVIN_EXE + "' " + arguments;
  if (input) {
    marvin::audio::write_speech_file(in, input->audio);
    command += " --audio-in '" + in.string() + "' --audio-out '" + out.string() + "'";
  }
  marvin::test_support::ChildOptions options;
  options.environment = {"MARVIN_DATA_DIR=" + (dir / "data").string()};
  options.in = marvin::test_support::ChildStream::kNull;
  marvin::test_support::ChildProcess child =
      marvin::test_support::ChildProcess::shell(command, options);
  Result result;
  result.exit_code = marvin::test_support::exit_code(child.finish());
  result.lines = child.output_lines();
  result.errors = child.errors();
  if (fs::exists(out)) result.output = marvin::audio::read_speech_file(out);
  return result;
}

const std::string kHost = "run --sim --in-memory --time-zone UTC --clock 2026-11-21T15:05";

// The lines that start with `prefix`, in order.
std::vector<std::string> lines_starting(const Result& r, const std::string& prefix) {
  std::vector<std::string> out;
  for (const std::string& l : r.lines) {
    if (l.rfind(prefix, 0) == 0) out.push_back(l);
  }
  return out;
}

// The whole transcript, for failure messages.
std::string transcript(const Result& r) {
  std::string all;
  for (const std::string& l : r.lines) all += l + "\n";
  return all + r.errors;
}

bool has_line(const Result& r, const std::string& line) {
  for (const std::string& l : r.lines) {
    if (l == line) return true;
  }
  return false;
}

// RMS of the output between two times (ms from the start of the input).
double output_rms(const Result& r, double from_ms, double to_ms) {
  const auto from = static_cast<std::size_t>(from_ms * kRate / 1000.0);
  const auto to = std::min(r.output.size(), static_cast<std::size_t>(to_ms * kRate / 1000.0));
  if (from >= to) return 0.0;
  return rms(std::vector<std::int16_t>(r.output.begin() + static_cast<std::ptrdiff_t>(from),
                                       r.output.begin() + static_cast<std::ptrdiff_t>(to)));
}

double ms(std::size_t sample) { return 1000.0 * static_cast<double>(sample) / kRate; }

const std::string kRed = "[light: awaiting (red)]";
const std::string kGreen = "[light: listening (green)]";
const std::string kYellow = "[light: executing (yellow)]";

// The greeting "Hello, I'm Marvin." plays first, from sample 0; the tests let it finish.
constexpr int kAfterGreetingMs = 2500;

}  // namespace

TEST_CASE("\"marvin, what time is it\": the time skill answers, in the transcript and in the WAV") {
  Recording rec;
  rec.silence(kAfterGreetingMs).say("marvin, what time is it");
  const Result r = run_marvin(kHost, &rec);
  INFO(transcript(r));
  CHECK(r.exit_code == 0);
  CHECK(lines_starting(r, "You: ") == std::vector<std::string>{"You: what time is it"});
  CHECK(lines_starting(r, "Marvin: ") ==
        std::vector<std::string>{"Marvin: Hello, I'm Marvin.", "Marvin: It's 3:05 PM."});
  // Red at start, yellow while greeting, red; green while listening, yellow while the skill
  // acts and Marvin speaks, red again.
  CHECK(lines_starting(r, "[light:") ==
        std::vector<std::string>{kRed, kYellow, kRed, kGreen, kYellow, kRed});
  // The output lines up with the input and is at least as long.
  REQUIRE(r.output.size() >= rec.audio.size());
  const double end = ms(rec.pieces[0].speech_end);
  CHECK(output_rms(r, 0, 1000) > 1000.0);                    // the greeting
  CHECK(output_rms(r, kAfterGreetingMs - 500, end) < 50.0);  // quiet while the user speaks
  CHECK(output_rms(r, end, end + 150) < 50.0);               // the endpointer's silence
  CHECK(output_rms(r, end + 500, end + 1200) > 1000.0);      // "It's 3:05 PM."
  CHECK(output_rms(r, end + 3000, ms(rec.audio.size())) < 50.0);
}

TEST_CASE("a command without the wake word is ignored") {
  Recording rec;
  rec.silence(kAfterGreetingMs).say("what time is it").say("call anna");
  const Result r = run_marvin(kHost, &rec);
  INFO(transcript(r));
  CHECK(r.exit_code == 0);
  CHECK(lines_starting(r, "You: ").empty());
  CHECK(lines_starting(r, "Marvin: ") == std::vector<std::string>{"Marvin: Hello, I'm Marvin."});
  CHECK(lines_starting(r, "[light:") == std::vector<std::string>{kRed, kYellow, kRed});
  CHECK(output_rms(r, kAfterGreetingMs, ms(rec.audio.size())) < 50.0);
}

TEST_CASE("\"marvin\" and gibberish get the manager's no-match answer") {
  Recording rec;
  rec.silence(kAfterGreetingMs).say("marvin, blorf znak quibble tarradiddle", 300, 7000);
  const Result r = run_marvin(kHost, &rec);
  INFO(transcript(r));
  CHECK(r.exit_code == 0);
  CHECK(lines_starting(r, "You: ") == std::vector<std::string>{"You: (not understood)"});
  const std::vector<std::string> said = lines_starting(r, "Marvin: ");
  REQUIRE(said.size() == 2);
  CHECK(std::regex_match(said[1], std::regex("Marvin: Sorry, I don't know how to help with "
                                             "that\\. You can ask me, for example: \"[a-z' ]+\"\\.")));
  const double end = ms(rec.pieces[0].speech_end);
  CHECK(output_rms(r, end + 500, end + 2500) > 1000.0);
}

TEST_CASE("a reminder by voice: the question is answered without the wake word") {
  Recording rec;
  rec.silence(kAfterGreetingMs)
      .say("marvin, remind me to take my pills", 300, 3500)  // "When should I remind you?"
      .say("at eight p m", 300, 4000);
  const Result r = run_marvin(kHost, &rec);
  INFO(transcript(r));
  CHECK(r.exit_code == 0);
  CHECK(lines_starting(r, "You: ") ==
        std::vector<std::string>{"You: remind me to take my pills", "You: at eight pm"});
  CHECK(lines_starting(r, "Marvin: ") ==
        std::vector<std::string>{"Marvin: Hello, I'm Marvin.", "Marvin: When should I remind you?",
                                 "Marvin: OK, I'll remind you to take your pills today at 8 PM."});
  // The answer is heard without the wake word: green again straight after the question.
  CHECK(lines_starting(r, "[light:") ==
        std::vector<std::string>{kRed, kYellow, kRed, kGreen, kYellow, kGreen, kYellow, kRed});
  const double question_at = ms(rec.pieces[0].speech_end);
  const double answer_end = ms(rec.pieces[1].speech_end);
  CHECK(output_rms(r, question_at + 500, question_at + 1500) > 1000.0);  // the question
  CHECK(output_rms(r, ms(rec.pieces[1].begin), answer_end) < 50.0);       // the user answers
  CHECK(output_rms(r, answer_end + 500, answer_end + 2500) > 1000.0);     // the confirmation
}

TEST_CASE("\"marvin, stop\" during a long answer cuts it short in the output") {
  // The no-match answer is long (over four seconds); "marvin, stop" comes one second in.
  Recording rec;
  rec.silence(kAfterGreetingMs).say("marvin, blorf znak quibble tarradiddle", 300, 1000);
  rec.say("marvin, stop", 0, 4000);
  const Result r = run_marvin(kHost, &rec);
  INFO(transcript(r));
  CHECK(r.exit_code == 0);
  CHECK(lines_starting(r, "You: ") ==
        std::vector<std::string>{"You: (not understood)", "You: stop"});
  CHECK(has_line(r, "[speech cut short]"));
  const std::vector<std::string> said = lines_starting(r, "Marvin: ");
  REQUIRE(said.size() == 3);
  CHECK(said[2] == "Marvin: OK.");
  // Light: ... yellow while answering, green at "marvin" (the answer stops), yellow, red.
  const std::vector<std::string> lights = lines_starting(r, "[light:");
  CHECK(lights == std::vector<std::string>{kRed, kYellow, kRed, kGreen, kYellow, kGreen, kYellow,
                                           kRed});
  const std::size_t answer_start = rec.pieces[0].speech_end;
  const std::size_t answer_length =
      synthesizer()
          .synthesize("Sorry, I don't know how to help with that. You can ask me, for example: "
                      "\"what do i have today\".")
          .size();
  const double stop_said = ms(rec.pieces[1].begin);
  const double stop_end = ms(rec.pieces[1].speech_end);
  // Still answering when "marvin, stop" starts, and the answer would have gone on past it.
  CHECK(output_rms(r, stop_said - 600, stop_said) > 1000.0);
  REQUIRE(ms(answer_start + answer_length) > stop_end + 1000);
  // Cut: quiet from just after "marvin" until "OK." after the endpoint.
  CHECK(output_rms(r, stop_end - 250, stop_end + 150) < 50.0);
  CHECK(output_rms(r, stop_end + 400, stop_end + 900) > 1000.0);  // "OK."
}

TEST_CASE("bad input: a missing recording, --audio-in without --sim, no sound card") {
  Result r = run_marvin(kHost + " --audio-in /nonexistent/in.wav");
  CHECK(r.exit_code == 2);
  CHECK(r.errors.find("/nonexistent/in.wav") != std::string::npos);
  CHECK(r.lines.empty());

  r = run_marvin("run --in-memory --audio-in /nonexistent/in.wav");
  CHECK(r.exit_code == 2);
  CHECK(r.errors.find("add --sim") != std::string::npos);

  // Live mode on a device that does not exist (no machine has it, with or without a card).
  r = run_marvin("run --in-memory --audio-device marvin-test-no-such-card");
  CHECK(r.exit_code == 1);
  CHECK(r.errors.find("no microphone") != std::string::npos);
  CHECK(r.errors.find("\"marvin-test-no-such-card\"") != std::string::npos);
  CHECK(r.errors.find("--sim") != std::string::npos);
  CHECK(r.lines.empty());
}

TEST_CASE("the carer's web page is served in the voice mode too, and stops before the host") {
  const fs::path dir = temp_dir();
  const fs::path data = dir / "web-data";
  // The password the page needs, set as the carer does (`marvin web password`).
  marvin::test_support::ChildProcess password = marvin::test_support::ChildProcess::shell(
      std::string("printf 'voice page password\\n' | '") + MARVIN_EXE +
      "' web password --data-dir '" + data.string() + "'");
  REQUIRE(marvin::test_support::exit_code(password.finish()) == 0);
  // Quiet at the end, so the recording is still playing while the test uses the page.
  Recording rec;
  rec.silence(kAfterGreetingMs).say("marvin, what time is it").silence(6000);
  marvin::audio::write_speech_file(dir / "web.wav", rec.audio);
  marvin::test_support::ChildOptions options;
  options.in = marvin::test_support::ChildStream::kNull;
  marvin::test_support::ChildProcess host = marvin::test_support::ChildProcess::shell(
      std::string("'") + MARVIN_EXE + "' run --sim --data-dir '" + data.string() +
          "' --web-listen 127.0.0.1:0 --time-zone UTC --clock 2026-11-21T15:05 --audio-in '" +
          (dir / "web.wav").string() + "'",
      options);
  const std::string line = host.wait_for_line_containing("[web page: https://127.0.0.1:");
  const auto port = static_cast<std::uint16_t>(std::stoi(line.substr(line.rfind(':') + 1)));
  CHECK(port != 0);  // the port it got, not the 0 asked for
  // Logged in while Marvin listens: the page is the voice host's.
  marvin::web::test::Browser page(port, data / "web/cert.pem");
  REQUIRE(page.login("voice page password").status == 200);
  const nlohmann::json status = page.send("GET", "/api/status").json();
  CHECK(status["running"] == true);
  CHECK(marvin::test_support::exit_code(host.finish()) == 0);
  const std::vector<std::string> lines = host.output_lines();
  CHECK(std::find(lines.begin(), lines.end(), "You: what time is it") != lines.end());
  CHECK(std::find(lines.begin(), lines.end(), "Marvin: It's 3:05 PM.") != lines.end());
}

// Last in the file: run before the "marvin, stop" case, making this recording changed how
// that case's "marvin, stop" came out of espeak-ng in this process (heard as "darker").
TEST_CASE("\"marvin, speak slower\" by voice: understood, and confirmed") {
  Recording rec;
  rec.silence(kAfterGreetingMs).say("marvin, speak slower", 300, 3500);
  const Result r = run_marvin(kHost, &rec);
  INFO(transcript(r));
  CHECK(r.exit_code == 0);
  CHECK(lines_starting(r, "You: ") == std::vector<std::string>{"You: speak slower"});
  CHECK(lines_starting(r, "Marvin: ") ==
        std::vector<std::string>{"Marvin: Hello, I'm Marvin.", "Marvin: OK, I'll speak more slowly."});
}
