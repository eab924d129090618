// Built-in skill "navigation": "go to the kitchen", "come here", "turn left", "turn around",
// "where are you", "where am I", "how far is the kitchen", "go to sleep", through the Robot
// API's going-places calls (API 1.2). "stop" is the manager's: it cancels the running go_to,
// which stops the wheels before it returns.
#include <cctype>
#include <cmath>
#include <marvin/skill.hpp>
#include <string>

namespace {

// "The Kitchen" -> "kitchen", "your charger" -> "charger": how the robot's map compares names.
std::string plain(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* article : {"the ", "my ", "your ", "our ", "a "}) {
    const std::string a = article;
    if (s.rfind(a, 0) == 0) {
      s.erase(0, a.size());
      break;
    }
  }
  while (!s.empty() && (s.back() == '.' || s.back() == '!' || s.back() == ' ')) s.pop_back();
  return s;
}

class NavigationSkill : public marvin::Skill {
 public:
  using marvin::Skill::Skill;

  void handle(const marvin::Request& request) override {
    if (request.intent == "where") {
      std::optional<std::string> room = robot().where_am_i();
      robot().say(room ? "I'm in the " + *room + "." : "I'm in a doorway, between two rooms.");
    } else if (request.intent == "where_am_i") {
      where_is_user();
    } else if (request.intent == "come_here") {
      go("me", Lookup{}, "I'm here.");
    } else if (request.intent == "turn") {
      turn(request.utterance);
    } else if (request.intent == "rest") {
      rest();
    } else if (request.intent == "how_far") {
      how_far(plain(request.slots.value("place", std::string())));
    } else if (request.intent == "go_to") {
      const std::string place = plain(request.slots.value("place", std::string()));
      go(place, look_up(place), "");
    } else {
      throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + request.intent + "'");
    }
  }

 private:
  // "turn left" (a quarter turn), "turn a little to the right" (30 degrees), "turn around"
  // (half a turn). Said first, for someone who cannot see it.
  void turn(const std::string& utterance) {
    const std::string u = " " + utterance + " ";
    auto has = [&](const char* w) {
      return u.find(std::string(" ") + w + " ") != std::string::npos;
    };
    const bool left = has("left"), right = has("right");
    if (left == right) {  // neither side (or both): the other way round
      robot().say("Turning around.");
      robot().turn(180);
      return;
    }
    const bool little = has("little") || has("slightly") || has("bit");
    const int degrees = little ? 30 : 90;
    robot().say(std::string("Turning ") + (little ? "a little " : "") + "to the " +
                (left ? "left." : "right."));
    robot().turn(left ? degrees : -degrees);  // counter-clockwise positive
  }

  // "where am I": the room the map places the user in ("me", as "come here" uses it).
  // Someone who cannot see, or who has just woken, may not know.
  void where_is_user() {
    std::optional<nlohmann::json> me;
    try {
      me = robot().place_find("me");
    } catch (const marvin::Error&) {
      // An older host or no map: the same as not knowing.
    }
    const std::string room = me ? me->value("room", "") : "";
    robot().say(room.empty() ? "Sorry, I don't know where you are."
                             : "You're in the " + room + ".");
  }

  // "go to sleep", "go back to your charger", "you can go now": back to the charger when the
  // map has one (a place called "charger"), out of the way and charging. Marvin still
  // listens for its name, and says so: "sleep" must not sound like "deaf".
  void rest() {
    const char* wake = "Say \"Marvin\" when you need me.";
    const Lookup charger = look_up("charger");
    // No charger on the map, or an older host or no map: rest where it is.
    if (!charger.info) return robot().say(std::string("OK. ") + wake);
    go("charger", charger, std::string("I'm at my charger. ") + wake);
  }

  // "how far is the kitchen": metres along the path the robot would drive from where it
  // stands (the person asking is usually beside it), rounded as people say them.
  void how_far(const std::string& place) {
    const Lookup found = look_up(place);
    const std::string shown = shown_name(place, found);
    // An older host or no map: the same as not knowing how far.
    if (!found.can_tell) {
      return robot().say("Sorry, I can't tell how far " + shown + " is from here.");
    }
    if (!found.info) return robot().say("Sorry, I don't know where " + shown + " is.");
    const std::optional<nlohmann::json>& info = found.info;
    // A person is where the map last placed them, which may not be where they are now.
    const bool person = info->value("kind", "") == "person";
    std::string said = person ? "The last place I saw " + shown : shown;
    said[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(said[0])));
    std::optional<std::string> here = robot().where_am_i();
    const bool in_it = here && plain(*here) == plain(info->value("name", ""));
    if (info->value("kind", "") == "room" && in_it) {
      return robot().say("I'm in the " + *here + " now.");
    }
    if (!info->contains("distance_m")) {
      return robot().say("Sorry, I can't tell how far " + shown + " is from here.");
    }
    const double metres = info->at("distance_m").get<double>();
    const long whole = std::lround(metres);
    if (metres < 1.0) return robot().say(said + " is less than a metre away.");
    robot().say(said + " is about " +
                (whole == 1 ? std::string("a metre") : std::to_string(whole) + " metres") +
                " away.");
  }

  // What the map says of a place, asked once per request: `info` is nullopt for a name it
  // does not know. A host before API 1.3, or one without a map, cannot say (`can_tell`).
  struct Lookup {
    std::optional<nlohmann::json> info;
    bool can_tell = true;
  };
  Lookup look_up(const std::string& place) {
    Lookup found;
    try {
      found.info = robot().place_find(place);
    } catch (const marvin::Error&) {
      found.can_tell = false;
    }
    return found;
  }

  // How to say a place: "you", "Anna" (a person: as the map spells the name, no "the"),
  // "the kitchen". Hosts that cannot tell people apart: "the" then.
  static std::string shown_name(const std::string& place, const Lookup& found) {
    if (place == "me") return "you";
    if (found.info && found.info->value("kind", "") == "person") {
      return found.info->value("name", place);
    }
    return "the " + place;
  }

  // `found`: look_up(place), done by the caller ("me" needs none).
  void go(const std::string& place, const Lookup& found, const std::string& arrived) {
    const std::string shown = shown_name(place, found);
    // Not "On my way" to somewhere it cannot go (a host that cannot tell: go_to will).
    if (place != "me" && found.can_tell && !found.info) {
      robot().say("Sorry, I don't know where " + shown + " is.");
      return;
    }
    try {
      robot().say("On my way to " + shown + ".");
      robot().go_to(place);
    } catch (const marvin::Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) {
        robot().say(place == "me" ? std::string("Sorry, I don't know where you are.")
                                  : "Sorry, I don't know where " + shown + " is.");
        return;
      }
      if (e.status() == MARVIN_ERR_UNAVAILABLE) {
        robot().say("Sorry, I can't get to " + shown + ": " + e.what() + ".");
        return;
      }
      throw;  // cancelled: the manager answers "OK, I stopped."
    }
    if (!arrived.empty()) {
      robot().say(arrived);
      return;
    }
    std::optional<std::string> room = robot().where_am_i();
    if (room && plain(*room) == place) {
      robot().say("I'm in the " + *room + ".");
    } else if (room) {
      robot().say("I'm at " + shown + ", in the " + *room + ".");
    } else {
      robot().say("I'm at " + shown + ".");
    }
  }
};

}  // namespace

MARVIN_SKILL(NavigationSkill, "navigation")
