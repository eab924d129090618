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
// says them.
#include <marvin/skill.hpp>
#include <optional>
#include <string>

#include "common/spoken_text.h"

namespace {

using marvin::builtin::lower;

using nlohmann::json;

constexpr std::chrono::seconds kPoll{1};
// Longer than the host's own "not answering" timeout (30 s): only reached if the host
// never says how the call went.
constexpr int kMaxQuietPolls = 45;

bool is_yes(const std::string& answer) {
  const std::string a = lower(answer);
  for (const char* yes : {"yes", "yeah", "yep", "sure", "ok", "okay", "please", "do it", "go ahead",
                          "call"}) {
    if (a.rfind(yes, 0) == 0) return true;
  }
  return false;
}

// "call for help" heard as "call {who}" with who = "for help".
bool means_help(const std::string& who) {
  const std::string w = lower(who);
  return w == "for help" || w == "help" || w == "an ambulance" || w == "someone for help" ||
         w == "emergency" || w == "the emergency";
}

class PhoneSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    const std::string& intent = request.intent;
    if (intent == "call") {
      auto it = request.slots.find("who");
      std::string who = it != request.slots.end() && it->is_string() ? it->get<std::string>() : "";
      if (means_help(who)) return call_for_help();
      return call(who);
    }
    if (intent == "hang_up") return hang_up();
    if (intent == "answer") return answer();
    if (intent == "decline") return decline();
    if (intent == "emergency") return call_for_help();
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

  void call(const std::string& who) {
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
    if (!is_yes(robot().ask(callee.value("say", "Call " + name + "?")))) {
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
