// The language-understanding tools, on the skills `marvin run` would load:
//   marvin nlu explain "TEXT"   normalised words, the request without politeness, the ranked
//                               intents with the model's probabilities and template costs,
//                               the decision and the slots
//   marvin nlu eval FILE.tsv    lines `utterance<TAB>label` ("none" = out of scope): accuracy
//                               per label, the confusions, and how often out-of-scope requests
//                               were acted on
//   marvin nlu eval FILE.tsv --half a|b   only the lines whose utterance's FNV-1a hash is even
//                               (a) or odd (b): tune on one half, check on the other, so
//                               that a change that only fits the sentences it was tuned on
//                               shows as a gap between the halves
//
// Labels: a request is right when the intent chosen carries the line's label. An intent's
// label comes from interpret::default_eval_labels() (the names of the shared development set)
// or from --labels FILE (lines `skill/intent<TAB>label`, `skill/*` for every intent of a
// skill), else it is the intent's own name. The dialogue words map to yes, no, cancel (stop)
// and repeat. Labels no loaded skill carries are listed but not scored (their skill is missing).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli.h"
#include "interpret/beyond_reach.h"
#include "interpret/eval_labels.h"
#include "app/host.h"
#include "app/installed_skills.h"
#include "common/log.h"
#include "skills/api_json.h"

namespace marvin::app {
namespace {

struct NluOptions {
  std::vector<std::string> skills_dirs;
  bool no_builtin = false;
  std::string time_zone;
  std::string labels_file;
  std::string text;
  std::string file;
  std::string half;  // "", "a" or "b"
  bool verbose = false;
};

// 32-bit FNV-1a: a fixed split of a file's lines that needs no random seed.
std::uint32_t fnv1a(const std::string& text) {
  std::uint32_t h = 2166136261U;
  for (char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 16777619U;
  }
  return h;
}

class Labels {
 public:
  explicit Labels(const std::string& file) {
    for (const auto& [key, label] : interpret::default_eval_labels()) labels_[key] = label;
    if (file.empty()) return;
    std::ifstream in(file);
    if (!in) throw CliError("--labels: cannot read " + file, 1);
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      if (line.empty() || line[0] == '#') continue;
      auto tab = line.find('\t');
      if (tab == std::string::npos || line.find('/') > tab) {
        throw CliError(file + ":" + std::to_string(number) +
                           ": expected `skill/intent<TAB>label`", 1);
      }
      labels_[line.substr(0, tab)] = line.substr(tab + 1);
    }
  }
  std::string of(const std::string& skill, const std::string& intent) const {
    if (auto it = labels_.find(skill + "/" + intent); it != labels_.end()) return it->second;
    if (auto it = labels_.find(skill + "/*"); it != labels_.end()) return it->second;
    return intent;
  }

 private:
  std::map<std::string, std::string> labels_;
};

std::unique_ptr<Host> load_host(const NluOptions& o) {
  set_log_level(o.verbose ? LogLevel::kInfo : LogLevel::kError);
  HostOptions h;
  for (const auto& dir : o.skills_dirs) h.skills_dirs.emplace_back(dir);
  if (o.skills_dirs.empty()) {
    if (auto installed = default_installed_skills_dir()) h.installed_skills_dir = *installed;
  }
  h.builtin_skills = !o.no_builtin;
  h.in_memory_data = true;  // understanding only: nothing is stored or read
  h.time_zone = o.time_zone.empty() ? system_time_zone() : o.time_zone;
  auto host = std::make_unique<Host>(std::move(h), [](std::string_view) {});
  host->load();
  for (const auto& error : host->registry().errors()) {
    std::fprintf(stderr, "marvin: skill not loaded: %s: %s\n", error.where.string().c_str(),
                 error.message.c_str());
  }
  return host;
}

interpret::Context nlu_context(const NluOptions& o) {
  interpret::Context c;
  c.now_utc_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                     std::chrono::system_clock::now().time_since_epoch())
                     .count();
  c.time_zone = o.time_zone.empty() ? system_time_zone() : o.time_zone;
  return c;
}

std::string fixed_nlu(double value, int decimals) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string join_nlu_words(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

void explain(const NluOptions& o) {
  auto host = load_host(o);
  const auto& interpreter = host->registry().interpreter();
  if (const char* b = interpret::builtin_eval_label(interpreter.builtin(o.text))) {
    write_line(std::string("dialogue word: ") + b + " (always checked first)");
  }
  interpret::Understanding u = interpreter.understand(o.text, nlu_context(o));
  write_line("normalised: " + join_nlu_words(u.words));
  write_line("request:    " + join_nlu_words(u.request));
  write_line("ranking:");
  for (const auto& r : u.ranking) {
    std::string name = r.skill_id.empty() ? "(out of scope)" : r.skill_id + "/" + r.intent;
    write_line("  " + fixed_nlu(r.probability, 3) + "  " + name +
               (r.cost >= 0 ? "  template cost " + fixed_nlu(r.cost, 2) : ""));
  }
  auto slots = [](const interpret::Match& m) {
    for (const auto& [name, value] : m.slots) {
      write_line("  slot " + name + " = \"" + value.text + "\" -> " + value.value.dump());
    }
  };
  switch (u.outcome) {
    case interpret::Understanding::Outcome::kMatch:
      write_line("decision: " + u.match->skill_id + "/" + u.match->intent + " (" + u.reason + ")");
      slots(*u.match);
      break;
    case interpret::Understanding::Outcome::kAsk:
      write_line("decision: ask between " + u.choices[0].skill_id + "/" + u.choices[0].intent +
                 " and " + u.choices[1].skill_id + "/" + u.choices[1].intent + " (" + u.reason +
                 ")");
      break;
    case interpret::Understanding::Outcome::kNone:
      write_line("decision: decline (" + u.reason + ")");
      if (auto why = interpret::beyond_reach(o.text)) write_line("reply: " + *why);
      break;
  }
}

void eval(const NluOptions& o) {
  std::ifstream in(o.file);
  if (!in) throw CliError("cannot read " + o.file, 1);
  auto host = load_host(o);
  const auto& interpreter = host->registry().interpreter();
  const Labels labels(o.labels_file);
  std::set<std::string> served{"yes", "no", "cancel", "repeat"};
  for (const auto& skill : host->registry().skills()) {
    for (const auto& intent : skill->manifest.intents) {
      served.insert(labels.of(skill->manifest.id, intent.name));
    }
  }
  const interpret::Context context = nlu_context(o);
  struct Tally {
    int total = 0, right = 0, asked = 0;
  };
  std::map<std::string, Tally> per_label;
  std::map<std::string, int> confusions;
  int none_total = 0, none_acted = 0, none_asked = 0;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    auto tab = line.rfind('\t');
    if (tab == std::string::npos) {
      throw CliError(o.file + ":" + std::to_string(number) + ": expected `utterance<TAB>label`",
                     1);
    }
    std::string text = line.substr(0, tab);
    std::string gold = line.substr(tab + 1);
    if (!o.half.empty() && (fnv1a(text) % 2 == 0) != (o.half == "a")) continue;
    std::string predicted = "none";
    bool asked = false;
    std::vector<std::string> asked_labels;
    if (const char* b = interpret::builtin_eval_label(interpreter.builtin(text))) {
      predicted = b;
    } else {
      interpret::Understanding u = interpreter.understand(text, context);
      if (u.outcome == interpret::Understanding::Outcome::kMatch) {
        predicted = labels.of(u.match->skill_id, u.match->intent);
      } else if (u.outcome == interpret::Understanding::Outcome::kAsk) {
        asked = true;
        for (const auto& c : u.choices) asked_labels.push_back(labels.of(c.skill_id, c.intent));
        predicted = "ask:" + asked_labels[0] + "|" + asked_labels[1];
      }
    }
    Tally& t = per_label[gold];
    ++t.total;
    bool right = predicted == gold ||
                 (asked && std::find(asked_labels.begin(), asked_labels.end(), gold) !=
                               asked_labels.end());
    if (gold == "none") {
      ++none_total;
      right = predicted == "none" || asked;
      if (asked) ++none_asked;
      if (!right) ++none_acted;
    }
    if (right) ++t.right;
    if (asked) ++t.asked;
    if (!right) ++confusions[gold + " -> " + predicted];
    if (!right && o.verbose) write_line("  wrong: " + text + "\t" + gold + " -> " + predicted);
  }
  write_line("label            right/total  accuracy  (asked)");
  int scored_total = 0, scored_right = 0;
  for (const auto& [label, t] : per_label) {
    if (label == "none") continue;
    bool scored = served.count(label) != 0;
    write_line((label + std::string(17 - std::min<std::size_t>(16, label.size()), ' ')) +
               std::to_string(t.right) + "/" + std::to_string(t.total) + "  " +
               fixed_nlu(100.0 * t.right / std::max(1, t.total), 1) + "%  (" +
               std::to_string(t.asked) + ")" + (scored ? "" : "  [no skill loaded: not scored]"));
    if (scored) {
      scored_total += t.total;
      scored_right += t.right;
    }
  }
  write_line("in scope, skills loaded: " + std::to_string(scored_right) + "/" +
             std::to_string(scored_total) + " = " +
             fixed_nlu(100.0 * scored_right / std::max(1, scored_total), 1) + "% right intent");
  write_line("out of scope acted on: " + std::to_string(none_acted) + "/" +
             std::to_string(none_total) + " = " +
             fixed_nlu(100.0 * none_acted / std::max(1, none_total), 1) + "% (asked instead: " +
             std::to_string(none_asked) + ")");
  std::vector<std::pair<int, std::string>> sorted;
  for (const auto& [what, count] : confusions) sorted.emplace_back(count, what);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  write_line("confusions (label -> chosen):");
  for (const auto& [count, what] : sorted) write_line("  " + std::to_string(count) + "  " + what);
}

void add_nlu_options(CLI::App& app, NluOptions& o) {
  app.add_option("--skills-dir", o.skills_dirs,
                 "Load the skills in this directory instead of the installed skills; repeatable");
  app.add_flag("--no-builtin-skills", o.no_builtin, "Do not load the build's built-in skills");
  app.add_option("--time-zone", o.time_zone, "The owner's IANA time zone (default: the system's)");
  app.add_flag("-v,--verbose", o.verbose, "Show every wrong answer (eval) and the host's log");
}

void install_nlu_commands(CLI::App& root) {
  auto options = std::make_shared<NluOptions>();
  CLI::App& nlu = command_group(root, "nlu", "Language understanding: explain and evaluate");
  CLI::App* explain_cmd = nlu.add_subcommand("explain", "How Marvin reads one request");
  explain_cmd->add_option("text", options->text, "The request")->required();
  add_nlu_options(*explain_cmd, *options);
  explain_cmd->callback([options] { explain(*options); });
  CLI::App* eval_cmd =
      nlu.add_subcommand("eval", "Accuracy on a file of `utterance<TAB>label` lines");
  eval_cmd->add_option("file", options->file, "The .tsv file")->required();
  eval_cmd->add_option("--labels", options->labels_file,
                       "Lines `skill/intent<TAB>label` mapping intents to the file's labels");
  eval_cmd->add_option("--half", options->half,
                       "Only half the lines, split by a hash of the utterance: a or b")
      ->check(CLI::IsMember({"a", "b"}));
  add_nlu_options(*eval_cmd, *options);
  eval_cmd->callback([options] { eval(*options); });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_nlu_commands);

}  // namespace marvin::app
