// Built-in skill "phone": phone calls by voice through the Robot API's phone calls (1.3).
//   "call my daughter"   "phone Anna"   "ring the doctor"   "call 0123 456 789"
//   "hang up"            "answer"       "decline"           "call for help"
// Whom a phrase means is the host's (phone_resolve: contacts, relations, nicknames,
// numbers); the skill asks between two, confirms ("Call Anna Schmidt?"), dials and says
// the progress until the other side answers, the line is busy or nobody answers. The
// call itself stays up after the skill returns: "hang up" ends it later. "Stop" while it
// rings cancels the request and the skill hangs up. Incoming calls are announced by the
// host ("Anna is calling"); "answer" and "decline" come here. "Call for help" asks
// nothing: the host calls the emergency contacts in order and logs every step; the skill
// says them. "I don't feel well" offers to call for help; "I'm lonely" / "I feel sad" offers to
// call someone (the person the answer names, or asks whom). "Did anyone call?" reads the
// calls of the last day from the event log the host keeps ("You missed a call from Anna 2
// hours ago.").
#include <algorithm>
#include <cctype>
#include <marvin/skill.hpp>
#include <optional>
#include <string>

#include "common/spoken_text.h"

namespace {

using marvin::builtin::ago;
using marvin::builtin::join_and;
using marvin::builtin::lower;
using marvin::builtin::words_in;

using nlohmann::json;

constexpr std::chrono::seconds kPoll{1};
// Longer than the host's own "not answering" timeout (30 s): only reached if the host
// never says how the call went.
constexpr int kMaxQuietPolls = 45;

// "Call Anna?" - "call her": a yes too, unless a no is in it ("call? no, don't").
bool is_yes(const std::string& answer) {
  return marvin::builtin::said_yes(answer) ||
         (lower(answer).rfind("call", 0) == 0 && marvin::builtin::said_yes("yes " + answer));
}

// "call for help" heard as "call {who}" with who = "for help".
bool means_help(const std::string& who) {
  const std::string w = lower(who);
  return w == "for help" || w == "help" || w == "someone for help" || w == "emergency" ||
         w == "the emergency";
}

// "call an ambulance", "phone the police": a public service, which Marvin cannot dial unless
// the owner saved it as a contact. Returns what to call it ("the police"), or "".
std::string emergency_service(const std::string& who) {
  std::string w = lower(who);
  for (const char* article : {"the ", "an ", "a "}) {
    if (w.rfind(article, 0) == 0) w.erase(0, std::string(article).size());
  }
  for (const char* service : {"ambulance", "police", "emergency services", "fire brigade",
                              "fire department", "fire service", "paramedics", "emergency number",
                              "emergency service"}) {
    if (w == service) return w == "ambulance" ? "an ambulance" : "the " + w;
  }
  return "";
}

// "I want to talk to you", "can I speak to you for a moment": Marvin is meant, not a call.
bool means_me(const std::string& who) {
  const std::string w = " " + lower(who) + " ";
  return w.rfind(" you ", 0) == 0 || (w.size() >= 5 && w.compare(w.size() - 5, 5, " you ") == 0);
}

// "I need to talk to someone": a call, to whom is still to be asked.
bool means_anyone(const std::string& who) {
  const std::string w = lower(who);
  return w == "someone" || w == "somebody" || w == "anyone" || w == "anybody" ||
         w == "a person" || w == "someone please";
}

// Whom an answer to "Shall I call ...?" names: "yes, call my daughter" -> "my daughter",
// "Anna please" -> "Anna"; "" for a bare yes or no.
std::string named_callee(const std::string& answer) {
  std::string a = lower(answer);
  for (char& c : a) {
    if (c == ',' || c == '.' || c == '!' || c == '?') c = ' ';
  }
  auto drop = [&](const char* word) {
    const std::string w = std::string(word) + " ";
    if ((a + " ").rfind(w, 0) != 0) return false;
    a = a.size() > w.size() ? a.substr(w.size()) : "";
    a.erase(0, a.find_first_not_of(' '));
    return true;
  };
  while (drop("yes") || drop("yeah") || drop("ok") || drop("okay") || drop("please") ||
         drop("call") || drop("phone") || drop("ring") || drop("up")) {
  }
  for (const char* tail : {" please", " for me", " now"}) {
    const std::string t = tail;
    while (a.size() > t.size() && a.compare(a.size() - t.size(), t.size(), t) == 0) {
      a.erase(a.size() - t.size());
    }
  }
  while (!a.empty() && a.back() == ' ') a.pop_back();
  static const char* kNotNames[] = {"no",      "nope",     "not now",   "not really",
                                    "nobody",  "sure",     "do it",     "go ahead",
                                    "someone", "somebody", "never mind"};
  for (const char* n : kNotNames) {
    if (a == n || a.rfind(std::string(n) + " ", 0) == 0) return "";
  }
  return a;
}

// Whether any word of `utterance` is one of `words`.
template <std::size_t N>
bool has_word(const std::string& utterance, const char* const (&words)[N]) {
  for (const std::string& said : words_in(utterance)) {
    for (const char* w : words) {
      if (said == w) return true;
    }
  }
  return false;
}

// True when a request says its speaker feels bad: "i do not feel well", "i feel
// dizzy", "i am a bit under the weather", "i slipped"; false for "i feel great".
bool says_unwell(const std::string& utterance) {
  static const char* const kBad[] = {
      "not",      "no",       "don't",     "dont",     "can't",   "isn't",   "sick",
      "ill",      "unwell",   "dizzy",     "faint",    "poorly",  "awful",   "terrible",
      "bad",      "weak",     "pain",      "pains",    "hurt",    "hurts",   "weather",
      "nauseous", "queasy",   "rough",     "funny",    "strange", "worse",   "off",
      "shaky",    "ache",     "aches",     "aching",   "headache", "migraine", "fever",
      "cough",    "cold",     "sore",      "toothache", "backache", "earache", "temperature",
      "cut",      "burnt",    "burned",    "doctor",   "slipped", "tripped", "fell",
      "fallen"};
  return has_word(utterance, kBad);
}

// True when a request says its speaker feels fine: "i feel great", "i'm feeling better".
bool says_well(const std::string& utterance) {
  static const char* const kGood[] = {"great",     "good",    "fine",      "better", "well",
                                      "fantastic", "wonderful", "happy",   "excellent",
                                      "brilliant", "okay",    "ok",        "relaxed", "lovely",
                                      "marvellous", "super",  "grand"};
  return has_word(utterance, kGood);
}

// "anna back", "my son on his mobile": whom to call, without how or when.
std::string callee_only(std::string who) {
  auto ends_with = [&](const std::string& tail) {
    return who.size() > tail.size() &&
           who.compare(who.size() - tail.size(), tail.size(), tail) == 0;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (const char* tail : {" back", " again", " right away", " straight away"}) {
      if (ends_with(tail)) {
        who.erase(who.size() - std::string(tail).size());
        changed = true;
      }
    }
    // " on his mobile", " at her home number", " on the landline"
    for (const char* on : {" on ", " at "}) {
      const std::size_t at = who.rfind(on);
      if (at == std::string::npos || at == 0) continue;
      const std::vector<std::string> rest = words_in(who.substr(at + std::string(on).size()));
      static const char* kHow[] = {"his",    "her",   "their", "the",      "my",     "mobile",
                                   "phone",  "cell",  "home",  "landline", "number", "work",
                                   "office", "house", "cellphone"};
      auto said_how = [](const std::string& w) {
        return std::any_of(std::begin(kHow), std::end(kHow), [&](const char* h) { return w == h; });
      };
      const bool how = !rest.empty() && std::all_of(rest.begin(), rest.end(), said_how);
      if (how) {
        who.erase(at);
        changed = true;
      }
    }
  }
  return who;
}

class PhoneSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    const std::string& intent = request.intent;
    if (intent == "call") {
      auto it = request.slots.find("who");
      std::string who = callee_only(
          it != request.slots.end() && it->is_string() ? lower(it->get<std::string>()) : "");
      if (means_help(who)) return call_for_help();
      if (const std::string service = emergency_service(who); !service.empty()) {
        json callee;
        if (!phone([&] { callee = robot().phone_resolve(who); })) return;
        const std::string kind = callee.value("kind", "unknown");
        if (kind == "contact" || kind == "number") return call(who, false);  // saved: no question
        robot().say("I can't call " + service + " myself, so I'm calling your emergency "
                    "contacts.");
        return call_for_help();
      }
      if (means_me(who)) {
        robot().say("I'm listening. What can I do for you?");
        return;
      }
      if (means_anyone(who)) {
        const std::string named = named_callee(robot().ask("Whom should I call?"));
        if (named.empty()) {
          robot().say("OK. I'm here if you need me.");
          return;
        }
        if (means_help(named)) return call_for_help();
        return call(named, false);
      }
      return call(who);
    }
    if (intent == "hang_up") return hang_up();
    if (intent == "answer") return answer();
    if (intent == "decline") return decline();
    if (intent == "emergency") return call_for_help();
    if (intent == "calls") return calls();
    if (intent == "unwell") return unwell(request.utterance);
    if (intent == "lonely") {
      auto it = request.slots.find("who");
      return lonely(it != request.slots.end() && it->is_string() ? it->get<std::string>() : "");
    }
  }

 private:
  // phone_* on a robot without a telephone, or one that cannot call now: say why.
  template <class F>
  bool phone(F&& body) {
    try {
      body();
      return true;
    } catch (const marvin::Error& e) {
      if (e.status() == MARVIN_ERR_UNAVAILABLE || e.status() == MARVIN_ERR_INVALID) {
        robot().say(std::string("I can't make the call: ") + e.what() + ".");
        return false;
      }
      throw;
    }
  }

  // The host logs "call_incoming" ("Anna is calling") for every call that rang and
  // "call_missed" ("You missed a call from Anna.") for those nobody took; each missed call
  // is paired with the latest call from the same name that rang before it.
  void calls() {
    constexpr std::int64_t kDayMs = 24LL * 60 * 60 * 1000;
    const std::int64_t now = robot().now_ms();
    json rang, missed;
    try {
      rang = robot().events_list("call_incoming", now - kDayMs);
      missed = robot().events_list("call_missed", now - kDayMs);
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      robot().say(std::string("Sorry, I can't tell who called: ") + e.what() + ".");
      return;
    }
    auto by_time = [](const json& a, const json& b) {
      return a.value("time_unix_ms", std::int64_t{0}) < b.value("time_unix_ms", std::int64_t{0});
    };
    std::sort(rang.begin(), rang.end(), by_time);
    std::sort(missed.begin(), missed.end(), by_time);
    auto name_in = [](const std::string& message, const std::string& before,
                      const std::string& after) {
      std::string m = message;
      if (m.rfind(before, 0) == 0) m.erase(0, before.size());
      if (m.size() >= after.size() &&
          m.compare(m.size() - after.size(), after.size(), after) == 0) {
        m.erase(m.size() - after.size());
      }
      return m;
    };
    std::vector<bool> was_missed(rang.size(), false);
    for (const json& m : missed) {
      const std::string who = name_in(m.value("message", ""), "You missed a call from ", ".");
      const std::int64_t at = m.value("time_unix_ms", std::int64_t{0});
      for (std::size_t i = rang.size(); i-- > 0;) {
        if (!was_missed[i] && rang[i].value("time_unix_ms", std::int64_t{0}) <= at &&
            name_in(rang[i].value("message", ""), "", " is calling") == who) {
          was_missed[i] = true;
          break;
        }
      }
    }
    std::vector<std::string> lost, taken;  // "from Anna 2 hours ago", "Anna called just now"
    for (std::size_t i = 0; i < rang.size(); ++i) {
      const std::string who = name_in(rang[i].value("message", ""), "", " is calling");
      const std::string when = ago(now - rang[i].value("time_unix_ms", now));
      if (was_missed[i])
        lost.push_back("from " + who + " " + when);
      else
        taken.push_back(who + " called " + when);
    }
    if (lost.empty() && taken.empty()) {
      robot().say("Nobody called in the last day.");
      return;
    }
    std::string text;
    if (lost.size() == 1) text = "You missed a call " + lost[0] + ".";
    if (lost.size() > 1) {
      text = "You missed " + std::to_string(lost.size()) + " calls: " + join_and(lost) + ".";
    }
    if (!taken.empty()) text += std::string(text.empty() ? "" : " ") + join_and(taken) + ".";
    robot().say(text);
  }

  // True when `who` is someone or a number the phone could call ("I'm fine" is not).
  bool callable(const std::string& who) {
    try {
      return robot().phone_resolve(who).value("kind", "unknown") != "unknown";
    } catch (const marvin::Error&) {
      return false;  // no telephone: call() will say so
    }
  }

  // Asks before anyone is called: feeling unwell is not yet an emergency. The intent model
  // hears "I feel great" close to "I don't feel good" (it weighs words, not their order), so
  // a request with a word of feeling fine and none of feeling bad is taken as the good news
  // it is; anything else ("I slipped") is asked about.
  void unwell(const std::string& utterance) {
    if (!says_unwell(utterance) && says_well(utterance)) {
      robot().say("I'm glad to hear that.");
      return;
    }
    const std::string answer =
        robot().ask("I'm sorry you're not feeling well. Shall I call for help?");
    const std::string named = named_callee(answer);
    if (!named.empty() && !means_help(named) && callable(named)) return call(named, false);
    if (is_yes(answer) || means_help(named)) return call_for_help();
    robot().say(
        "OK. If you feel worse, say \"call for help\" and I'll call your emergency "
        "contacts.");
  }

  // `missed`: "I miss my daughter" -> offers to call her.
  void lonely(const std::string& missed = "") {
    if (!missed.empty() && callable(missed)) {
      const std::string name = robot().phone_resolve(missed).value("name", missed);
      if (is_yes(robot().ask("I'm sure you do. Shall I call " + name + " for you?"))) {
        return call(missed, false);
      }
      robot().say("OK. I'm here if you need me.");
      return;
    }
    const std::string answer = robot().ask("I'm sorry to hear that. Shall I call someone for you?");
    std::string named = named_callee(answer);
    if (!named.empty() && !is_yes(answer) && !callable(named)) named.clear();  // "I'm fine"
    if (named.empty() && is_yes(answer)) named = named_callee(robot().ask("Whom should I call?"));
    if (named.empty()) {
      robot().say("OK. I'm here if you need me.");
      return;
    }
    if (means_help(named)) return call_for_help();
    call(named, false);
  }

  // `confirm`: ask "Call Anna Schmidt?" first; not when the user has just named whom to call
  // in answer to an offer.
  void call(const std::string& who, bool confirm = true) {
    json callee;
    if (!phone([&] { callee = robot().phone_resolve(who); })) return;
    std::string kind = callee.value("kind", "unknown");
    if (kind == "ambiguous") {
      const json candidates = callee["candidates"];
      const std::string answer = robot().ask(callee.value("say", "Whom do you mean?"));
      callee = robot().phone_resolve(answer);
      kind = callee.value("kind", "unknown");
      bool among = false;
      for (const json& c : candidates) among = among || c == callee["name"];
      if (kind != "no_number" && (kind != "contact" || !among)) {
        robot().say("Sorry, I still don't know whom you mean.");
        return;
      }
    }
    if (kind != "contact" && kind != "number") {
      robot().say(callee.value("say", "I don't know whom to call."));
      return;
    }
    const std::string number = callee.value("number", "");
    const std::string name = kind == "contact" ? callee.value("name", number) : number;
    if (confirm && !is_yes(robot().ask(callee.value("say", "Call " + name + "?")))) {
      robot().say("OK, I won't call.");
      return;
    }
    if (!phone([&] { robot().phone_dial(number, name); })) return;
    follow(name);
  }

  // Says how the call placed to `name` goes, until it is answered or over.
  void follow(const std::string& name) {
    int quiet = 0;
    bool said_ringing = false;
    for (;;) {
      std::optional<json> event;
      try {
        event = robot().phone_wait_event(kPoll);
      } catch (const marvin::Error& e) {
        if (e.status() != MARVIN_ERR_CANCELLED) throw;
        hang_up_quietly();  // "stop": the host already said "OK, I stopped."
        return;
      }
      if (!event) {
        if (++quiet < kMaxQuietPolls) continue;
        hang_up_quietly();
        robot().say(name + " is not answering.");
        return;
      }
      const std::string what = event->value("event", "");
      if (what == "ringing") {
        if (!said_ringing) robot().say("Ringing " + name + ".");
        said_ringing = true;
      } else if (what == "answered") {
        robot().say("You're connected to " + name + ".");
        return;
      } else if (what == "busy") {
        robot().say("The line is busy. " + name + " can't take the call now.");
        return;
      } else if (what == "no_answer") {
        robot().say(name + " is not answering.");
        return;
      } else if (what == "failed") {
        const std::string reason = event->value("reason", "");
        robot().say("I couldn't reach " + name + (reason.empty() ? "" : " (" + reason + ")") + ".");
        return;
      } else if (what == "ended") {
        robot().say("The call with " + name + " has ended.");
        return;
      }
    }
  }

  void hang_up_quietly() {
    try {
      robot().phone_hang_up();
    } catch (const marvin::Error&) {
      // Already over: nothing to hang up.
    }
  }

  static std::string who_of(const json& state) {
    std::string name = state.value("name", "");
    return name.empty() ? state.value("number", "") : name;
  }

  // "hang up", "answer", "decline": `act` on the call now; says `nothing` when there is no
  // such call (MARVIN_ERR_NOT_FOUND), else what `done` makes of the other side's name.
  template <class Act, class Done>
  void on_the_call(Act act, const char* nothing, Done done) {
    json state;
    if (!phone([&] { state = robot().phone_state(); })) return;
    try {
      act();
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_NOT_FOUND) throw;
      robot().say(nothing);
      return;
    }
    robot().say(done(who_of(state)));
  }

  void hang_up() {
    on_the_call([&] { robot().phone_hang_up(); }, "There is no call to hang up.",
                [](const std::string& who) {
                  return who.empty() ? "OK, I hung up."
                                     : "OK, I hung up. The call with " + who + " has ended.";
                });
  }

  void answer() {
    on_the_call([&] { robot().phone_answer(); }, "Nobody is calling.",
                [](const std::string& who) { return "You're connected to " + who + "."; });
  }

  void decline() {
    on_the_call([&] { robot().phone_decline(); }, "Nobody is calling.",
                [](const std::string& who) { return "I declined the call from " + who + "."; });
  }

  void call_for_help() {
    try {
      robot().phone_call_for_help();
    } catch (const marvin::Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) {
        robot().say("I have no emergency contact to call. Add one with marvin contacts add "
                    "--emergency 1.");
        return;
      }
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      robot().say(std::string("I can't call for help: ") + e.what() + ".");
      return;
    }
    for (;;) {
      std::optional<json> event;
      try {
        event = robot().phone_wait_event(kPoll);
      } catch (const marvin::Error& e) {
        if (e.status() != MARVIN_ERR_CANCELLED) throw;
        hang_up_quietly();
        return;
      }
      if (!event) continue;  // each attempt ends by itself (answered, busy, not answering)
      const std::string what = event->value("event", "");
      if (what == "emergency_step") robot().say(event->value("text", "") + ".");
      if (what == "emergency_done") {
        const std::string by = event->value("answered_by", "");
        if (!by.empty()) robot().say("You're connected to " + by + ".");
        return;
      }
    }
  }
};

}  // namespace

MARVIN_SKILL(PhoneSkill, "phone")
