// Built-in skill "finding" (issue 22), on the Robot API 1.3 finding-and-guarding calls:
//   "where is Anna?" / "have you seen my keys?"  -> from memory (the sightings) when recent,
//        else it searches
//   "find Anna" / "find my keys"                 -> searches: the room it was last seen in
//        first, then the rooms in the robot's planned order; at each it looks around
//   "is anyone in the kitchen?"                  -> goes there, looks around, says who
//   "is anyone here?" / "is anyone home?"        -> this room / every room in turn
//   "who is at the door?"                        -> goes to the front door, says whom it
//                                                   sees (a closed door hides the caller)
//   "tell Anna dinner is ready"                  -> finds her, goes to her, says it
//   "I'm going out" / "guard the house"          -> guard mode on
//   "I'm home" / "stop guarding"                 -> off, only when it sees a face it knows
//   "who came while I was out?"                  -> the intruder events since guarding began
// Who is a person: someone on the map (people's last known spots), enrolled by face, or
// seen as a person before; anything else is a thing ("my keys", "the dog").
#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include <marvin/skill.hpp>

#include "common/spoken_text.h"

namespace {

using marvin::builtin::ago;
using marvin::builtin::capitalised;
using marvin::builtin::join_and;
using marvin::builtin::lower;

using nlohmann::json;

// A sighting this recent answers "where is ...?" without searching.
constexpr std::int64_t kRecentMs = 30 * 60 * 1000;

std::string trim_end(std::string s) {
  while (!s.empty() && (s.back() == '?' || s.back() == '.' || s.back() == '!' || s.back() == ' '))
    s.pop_back();
  return s;
}

std::string strip_prefix(std::string s, const char* prefix) {
  const std::string p = prefix;
  if (s.rfind(p, 0) == 0) s.erase(0, p.size());
  return s;
}

// What the user is looking for, and how to say it back.
struct Wanted {
  std::string key;    // as the sightings and the camera name it: "Anna", "keys"
  bool person = false;
  bool mine = false;  // "my keys"
  std::string said() const { return person ? key : (mine ? "your " : "the ") + key; }
  // "keys", "glasses" are plural; "dress", "bus", "iris" and people are not.
  bool plural() const {
    if (person || key.size() < 3 || key.back() != 's') return false;
    const char before = key[key.size() - 2];
    return before != 's' && before != 'u' && before != 'i';
  }
  std::string verb() const { return plural() ? "are" : "is"; }  // "is" / "are"
  std::string them() const { return plural() ? "them" : "it"; }
};

// "wife", "grandson": someone, not a thing, though no contact has that relation.
bool is_relation(const std::string& word) {
  static const char* kRelations[] = {
      "wife",          "husband",     "partner",     "daughter", "son",           "child",
      "children",      "kids",        "mother",      "father",   "mum",           "mom",
      "dad",           "sister",      "brother",     "grandson", "granddaughter", "grandchild",
      "grandchildren", "grandmother", "grandfather", "grandma",  "grandpa",       "niece",
      "nephew",        "aunt",        "uncle",       "cousin",   "carer",         "caregiver",
      "nurse",         "neighbour",   "neighbor",    "friend",   "family"};
  for (const char* r : kRelations) {
    if (word == r) return true;
  }
  return false;
}

// "in the kitchen, near the kitchen table"
std::string where_words(const json& s) {
  std::string out;
  const std::string room = s.value("room", "");
  const std::string near = s.value("near", "");
  if (!room.empty()) out += "in the " + room;
  if (!near.empty()) out += std::string(out.empty() ? "" : ", ") + "near the " + near;
  return out.empty() ? "somewhere I can't name" : out;
}

class FindingSkill : public marvin::Skill {
 public:
  using Skill::Skill;

  void handle(const marvin::Request& r) override {
    yes_no_ = true;
    try {
      if (r.intent == "where_is") where_is(wanted(r.slots.value("what", std::string())), false);
      else if (r.intent == "find") where_is(wanted(r.slots.value("what", std::string())), true);
      else if (r.intent == "anyone_in") {
        std::string room = trim_end(lower(r.slots.value("room", std::string())));
        // "is anyone here?" names no room (the template has none): this room.
        const std::string said = trim_end(lower(r.utterance));
        if (room.empty() && said.size() >= 5 && said.compare(said.size() - 5, 5, " here") == 0) {
          room = "here";
        }
        // "who is at the door?" names no room either.
        if (room.empty() && said.size() >= 5 && said.compare(said.size() - 5, 5, " door") == 0) {
          room = "the door";
        }
        // "is anyone in the kitchen?" is answered "Yes: ..." or "No, ..."; "who is in the
        // kitchen?" or "there's someone at the door" with what the robot saw alone.
        yes_no_ = said.rfind("is ", 0) == 0 || said.rfind("are ", 0) == 0 ||
                  said.rfind("any", 0) == 0;
        anyone_in(room);
      }
      else if (r.intent == "tell") tell(r.slots.value("name", std::string()),
                                        trim_end(r.slots.value("message", std::string())));
      else if (r.intent == "guard_on") guard_on();
      else if (r.intent == "guard_off") guard_off();
      else if (r.intent == "who_came") who_came();
      else throw marvin::Error(MARVIN_ERR_INVALID, "unknown intent '" + r.intent + "'");
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;  // cancelled: "OK, I stopped."
      robot().log(MARVIN_LOG_WARNING, e.what());
      robot().say(std::string("Sorry, I can't do that right now: ") + e.what() + ".");
    }
  }

 private:
  bool yes_no_ = true;  // this request asks yes or no ("is anyone in ...?"), not "who ...?"

  Wanted wanted(std::string what) {
    what = trim_end(lower(what));
    // "I can't find my glasses, can you help me find them" fills "i can't find {what}" with
    // everything after "find": the thing ends where the request for help starts.
    for (const char* then : {" can you ", " could you ", " will you ", " would you ",
                             " please ", " help me ", " where ", " have you "}) {
      const std::size_t at = (what + " ").find(then);
      if (at != std::string::npos && at > 0) what.resize(at);
    }
    Wanted w;
    // "my daughter" is the contact whose relation that is: a person, by name.
    if (what.rfind("my ", 0) == 0) {
      const json contacts = robot().contacts_find(what);
      if (!contacts.empty()) {
        w.person = true;
        w.key = capitalised(contacts[0].value("name", what.substr(3)));
        return w;
      }
    }
    if (what.rfind("my ", 0) == 0) {
      w.mine = true;
      w.key = what.substr(3);
      return w;
    }
    w.key = strip_prefix(strip_prefix(what, "the "), "a ");
    w.person = is_person(w.key);
    if (w.person) w.key = capitalised(w.key);
    return w;
  }

  // Whether Marvin knows `name`'s face (enrolled: "this is Anna"); the camera cannot find a
  // person without it, however long the search.
  bool knows_face(const std::string& name) {
    for (const json& p : robot().people_list()) {
      if (lower(p.value("name", "")) == lower(name)) return true;
    }
    return false;
  }

  // Said instead of a search that cannot succeed.
  void say_face_unknown(const Wanted& w) {
    robot().say("I don't know " + w.key + "'s face yet, so I can't look for " + w.key + ". When " +
                w.key + " is in front of me, say \"this is " + w.key + "\".");
  }

  // "my wife" with no contact of that relation: how to add one.
  void say_relation_unknown(const std::string& relation) {
    robot().say("I don't know who your " + relation + " is. To tell me, say \"add a contact\".");
  }

  bool is_person(const std::string& name) {
    if (auto place = robot().place_find(name)) {
      if (place->value("kind", "") == "person") return true;
    }
    for (const json& p : robot().people_list()) {
      if (lower(p.value("name", "")) == name) return true;
    }
    for (const json& s : robot().sightings_find(name)) {
      if (s.value("kind", "") == "person") return true;
    }
    // A contact ("where is Tom", the son) is someone, though Marvin may not know the face.
    return !robot().contacts_find(name).empty();
  }

  // The newest sighting of `w`, if any.
  std::optional<json> last_seen(const Wanted& w) {
    for (const json& s : robot().sightings_find(w.key)) {
      if ((s.value("kind", "") == "person") == w.person) return s;
    }
    return std::nullopt;
  }

  void where_is(Wanted w, bool search_now) {
    if (w.key.empty()) {
      robot().say("Who or what should I look for?");
      return;
    }
    // "Where is the kitchen?", "where's the sofa?": rooms and furniture do not move; the
    // map knows where they are, no search needed.
    if (!w.person && !w.mine) {
      if (auto place = robot().place_find(w.key); place && place->value("kind", "") != "person") {
        return where_on_the_map(*place);
      }
    }
    const bool recognisable = !w.person && knows_look(w);
    const std::optional<json> seen = last_seen(w);
    const std::int64_t now = robot().now_ms();
    if (seen && !search_now && now - seen->value("seen_unix_ms", std::int64_t{0}) <= kRecentMs) {
      robot().say("I saw " + w.said() + " " + where_words(*seen) + ", " +
                  ago(now - seen->value("seen_unix_ms", now)) + ".");
      const std::string answer = lower(robot().ask("Shall I look again?"));
      if (!marvin::builtin::said_yes(answer)) {
        return;
      }
    }
    if (!w.person && !w.mine && !seen && !recognisable) {
      robot().say("I don't know who or what " + w.key + " is.");
      return;
    }
    if (w.person && !seen && !knows_face(w.key)) {
      say_face_unknown(w);
      return;
    }
    if (w.mine && !seen && !recognisable && is_relation(w.key)) return say_relation_unknown(w.key);
    if (!w.person && !seen && !recognisable) {
      robot().say("I don't know what " + w.said() + (w.plural() ? " look" : " looks") +
                  " like, and I have never seen " + (w.mine ? w.them() : w.said()) +
                  ". Show me and say \"" + (w.plural() ? "these are" : "this is") + " my " +
                  w.key + "\".");
      return;
    }
    std::string first;
    if (seen) first = seen->value("room", "");
    if (first.empty() && w.person) {
      if (auto place = robot().place_find(w.key)) first = place->value("room", "");
    }
    robot().say("I'll look for " + w.said() + ".");
    const Found found = search(w, first);
    if (found.where) {
      std::string sentence = capitalise_first(w.said()) + " " + w.verb() + " " + where_words(*found.where) + ".";
      robot().say(sentence);
      if (!w.person) offer_to_lead(*found.where);
      return;
    }
    say_not_found(w, found);
  }

  // Whether the camera can recognise `w`: a taught object, or a COCO class the host's
  // detector knows ("bike"). Renames `w` to what looks and sightings call it ("bicycle").
  bool knows_look(Wanted& w) {
    try {
      const std::optional<json> found = robot().vision_find_object(w.key);
      if (!found) return false;
      w.key = lower(found->value("name", w.key));
      return true;
    } catch (const marvin::Error&) {
      return false;
    }
  }

  struct Found {
    std::optional<json> where;
    std::vector<std::string> looked, unreachable;
    std::string camera_error;
  };

  // Goes into `room` for a search; one it cannot get to (blocked, not on the map) is added
  // to `unreachable` and false returned. "Stop" ends the search here.
  bool enter(const std::string& room, std::vector<std::string>& unreachable) {
    robot().check_cancelled();
    try {
      robot().go_to(room);
      return true;
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE && e.status() != MARVIN_ERR_NOT_FOUND) throw;
      unreachable.push_back(room);
      return false;
    }
  }

  // Visits rooms (`first`, then the planned order) and looks around in each until `w` is
  // seen. A room it cannot reach is skipped and named; a camera failure ends the search.
  Found search(const Wanted& w, const std::string& first) {
    Found f;
    std::vector<std::string> rooms = robot().rooms_to_search();
    if (!first.empty()) {
      rooms.erase(std::remove(rooms.begin(), rooms.end(), first), rooms.end());
      rooms.insert(rooms.begin(), first);
    }
    for (const std::string& room : rooms) {
      if (!enter(room, f.unreachable)) continue;
      json seen;
      try {
        seen = robot().look_around();
      } catch (const marvin::Error& e) {
        if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
        f.camera_error = e.what();
        f.looked.push_back(room);
        return f;
      }
      f.looked.push_back(room);
      robot().log(MARVIN_LOG_INFO, "looked around in the " + room + ": " + seen.dump());
      for (const json& s : seen.value("seen", json::array())) {
        const bool person = s.value("kind", "") == "person";
        if (person == w.person && lower(s.value("name", "")) == lower(w.key)) {
          f.where = s;
          return f;
        }
      }
      if (w.person) {
        if (auto closer = closer_look(w, room, seen.value("seen", json::array()))) {
          f.where = closer;
          return f;
        }
      }
    }
    return f;
  }

  // A face seen in `room` but not recognised may be who we look for, too far away: a face
  // about 2.5 m away is only some 40 pixels high, and recognition then fails about half the
  // time (the simulated home's living room spot is that far from Anna's). Go closer and look
  // again: to the person's spot on the map when it is in this room (arriving facing them),
  // else to the place or furniture the nearest such face was seen near (looking around).
  std::optional<json> closer_look(const Wanted& w, const std::string& room, const json& seen) {
    const json* nearest = nullptr;
    for (const json& s : seen) {
      if (s.value("kind", "") != "person" || !s.value("name", "").empty()) continue;
      if (s.value("room", "") != room) continue;
      if (!nearest || s.value("distance_m", 9.0) < nearest->value("distance_m", 9.0)) nearest = &s;
    }
    if (!nearest) return std::nullopt;
    robot().check_cancelled();
    auto found_in = [&](const json& faces) -> std::optional<json> {
      for (const json& face : faces) {
        if (lower(face.value("name", "")) != lower(w.key)) continue;
        json where = *nearest;
        where["name"] = w.key;
        if (face.contains("room")) where = face;
        return where;
      }
      return std::nullopt;
    };
    try {
      auto spot = robot().place_find(w.key);
      if (spot && spot->value("kind", "") == "person" && spot->value("room", "") == room) {
        robot().go_to(w.key);
        return found_in(robot().vision_look().value("faces", json::array()));
      }
      const std::string near = nearest->value("near", "");
      if (near.empty() || !robot().place_find(near)) return std::nullopt;
      robot().go_to(near);
      return found_in(robot().look_around().value("seen", json::array()));
    } catch (const marvin::Error& e) {
      // Not reachable or the camera failed: the search goes on (and names what failed).
      if (e.status() != MARVIN_ERR_UNAVAILABLE && e.status() != MARVIN_ERR_NOT_FOUND) throw;
      robot().log(MARVIN_LOG_WARNING, std::string("no closer look: ") + e.what());
      return std::nullopt;
    }
  }

  void say_not_found(const Wanted& w, const Found& f) {
    std::vector<std::string> rooms;
    for (const auto& r : f.looked) rooms.push_back("the " + r);
    std::string sentence;
    if (!f.camera_error.empty()) {
      sentence = "Sorry, my camera stopped working while I was looking for " + w.said() + ".";
      if (!rooms.empty()) sentence += " I had looked in " + join_and(rooms) + ".";
    } else {
      sentence = "I couldn't find " + w.said() + ".";
      if (!rooms.empty()) sentence += " I looked in " + join_and(rooms) + ".";
    }
    if (!f.unreachable.empty()) {
      std::vector<std::string> blocked;
      for (const auto& r : f.unreachable) blocked.push_back("the " + r);
      sentence += " I couldn't get into " + join_and(blocked) + ".";
    }
    robot().say(sentence);
  }

  // A room or a named place of the map: where it is, and the way there if wanted.
  void where_on_the_map(const json& place) {
    std::string name = place.value("name", "");
    if (lower(name).rfind("the ", 0) == 0) name.erase(0, 4);  // map places are "the sofa"
    const std::string room = place.value("room", name);
    const std::optional<std::string> here = robot().where_am_i();
    if (place.value("kind", "") == "room") {
      if (here && lower(*here) == lower(room)) return robot().say("We're in the " + room + ".");
      robot().say("The " + room + " is one of the rooms here" +
                  (here ? "; I'm in the " + *here : std::string()) + ".");
    } else {
      robot().say(capitalise_first("the " + name) + " is in the " + room +
                  (here && lower(*here) == lower(room) ? ", where we are." : "."));
      if (here && lower(*here) == lower(room)) return;
    }
    offer_to_lead(json{{"room", room}});
  }

  void offer_to_lead(const json& where) {
    const std::string room = where.value("room", "");
    if (room.empty()) return;
    const std::string answer = lower(robot().ask("Shall I show you the way?"));
    if (!marvin::builtin::said_yes(answer)) return;
    robot().go_to(room);
    robot().say("Here we are: the " + room + ".");
  }

  static std::string capitalise_first(std::string s) {
    if (!s.empty()) s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
    return s;
  }

  // "is anyone in the kitchen?", "is anyone here?" (this room, without moving), "is anyone
  // home?" (no room, or the whole home named: every room in turn).
  void anyone_in(const std::string& said_room) {
    const std::string said = strip_prefix(strip_prefix(said_room, "in "), "at ");
    if (said.empty() || means_whole_home(said)) return anyone_home();
    for (const char* door : {"the door", "the front door", "my door", "my front door", "door"}) {
      if (said == door) return at_the_door();
    }
    if (said == "here" || said == "the room" || said == "this room") {  // "in here" too
      const std::optional<std::string> here = robot().where_am_i();
      if (!here) return anyone_home();
      const std::vector<std::string> who = people_seen(robot().look_around());
      robot().say(who.empty() ? no() + "I don't see anyone here."
                              : yes(join_and(who) + are(who) + " here with us."));
      return;
    }
    const std::string name = strip_prefix(said, "the ");
    auto place = robot().place_find(name);
    if (!place || place->value("kind", "") == "person") {
      robot().say("I don't know a room called " + said_room + ".");
      return;
    }
    const std::string room = place->value("room", name);
    if (!reach(room, "the " + room)) return;
    const std::vector<std::string> who = people_seen(robot().look_around());
    if (who.empty()) {
      robot().say(no() + "I don't see anyone in the " + room + ".");
    } else {
      robot().say(yes(join_and(who) + are(who) + " in the " + room + "."));
    }
  }

  // Drives to `place`; false after telling the user why not ("I can't get to the kitchen:
  // the door is closed."), `spoken` being how the place is named.
  bool reach(const std::string& place, const std::string& spoken) {
    try {
      robot().go_to(place);
      return true;
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      robot().say("I can't get to " + spoken + ": " + e.what() + ".");
      return false;
    }
  }

  // The answer to a yes/no question starts with its "Yes: " or "No, "; to "who is ...?" not.
  std::string yes(const std::string& answer) const {
    return yes_no_ ? "Yes: " + answer : capitalise_first(answer);
  }
  std::string no() const { return yes_no_ ? "No, " : ""; }

  // "who is at the door?" (the doorbell rang): the robot goes to the front door and says
  // whom its camera sees there. A closed door hides whoever is outside, so seeing nobody
  // is said as that, with the advice a carer would give, not as "nobody is there".
  void at_the_door() {
    std::string door;
    for (const char* name : {"the front door", "the door", "the entrance"}) {
      const std::optional<json> place = robot().place_find(name);
      if (place && place->value("kind", "") != "person") {
        door = place->value("name", std::string(name));
        break;
      }
    }
    if (door.empty()) {
      robot().say("I don't know where your front door is: it isn't on my map.");
      return;
    }
    if (door.rfind("the ", 0) != 0) door = "the " + door;
    if (!reach(door, door)) return;
    json seen = json::array();
    for (const json& face : robot().vision_look().value("faces", json::array())) {
      seen.push_back({{"kind", "person"}, {"name", face.value("name", "")}});
    }
    const std::vector<std::string> who = people_seen(json{{"seen", seen}});
    if (who.empty()) {
      robot().say(no() + "I'm at " + door + " and I don't see anyone. If someone is outside, " +
                  "ask who it is before you open the door.");
    } else {
      robot().say(yes(join_and(who) + are(who) + " at " + door + "."));
    }
  }

  // " is" / " are" after people_seen's list: "Anna is", "two people I don't know are".
  static std::string are(const std::vector<std::string>& who) {
    const bool one = who.size() == 1 && who[0].rfind("two ", 0) != 0 &&
                     who[0].rfind("three ", 0) != 0 && who[0].rfind("several ", 0) != 0;
    return one ? " is" : " are";
  }

  static bool means_whole_home(const std::string& said) {
    for (const char* w : {"home", "the house", "the home", "the flat", "the apartment", "house",
                          "there", "around", "about", "anywhere", "the building"}) {
      if (said == w) return true;
    }
    return false;
  }

  // Every room in the planned order: who is where. A room it cannot reach is named.
  void anyone_home() {
    robot().say("I'll have a look around the house.");
    std::vector<std::string> found, looked, unreachable;
    for (const std::string& room : robot().rooms_to_search()) {
      if (!enter(room, unreachable)) continue;
      looked.push_back("the " + room);
      const std::vector<std::string> who = people_seen(robot().look_around());
      if (!who.empty()) {
        found.push_back(join_and(who) + are(who) + " in the " + room);
      }
    }
    std::string sentence;
    if (!found.empty()) {
      sentence = yes(join_and(found) + ".");
    } else if (!looked.empty()) {
      sentence = no() + "I didn't see anyone. I looked in " + join_and(looked) + ".";
    } else {
      sentence = "I couldn't look: I couldn't get into any room.";
    }
    if (!unreachable.empty() && !looked.empty()) {
      for (std::string& room : unreachable) room = "the " + room;
      sentence += " I couldn't get into " + join_and(unreachable) + ".";
    }
    robot().say(sentence);
  }

  // The people of a look_around, to be said: names first, then "someone I don't know".
  static std::vector<std::string> people_seen(const json& look) {
    std::vector<std::string> who;
    const int unknown = strangers(look.value("seen", json::array()), who);
    static const char* kCounts[] = {"", "someone I don't know", "two people I don't know",
                                    "three people I don't know"};
    if (unknown > 0) who.push_back(unknown < 4 ? kCounts[unknown] : "several people I don't know");
    return who;
  }

  // The people of a look_around: names into `known` (once each); returns how many
  // strangers. The same person is seen from several stops, and a known face far away is
  // sometimes not recognised: a face nobody enrolled within 1 m of another sighting (by
  // bearing and estimated distance) is that same person.
  static int strangers(const json& seen, std::vector<std::string>& known) {
    struct At {
      double x, y;
      bool named;
    };
    std::vector<At> people;
    auto at = [](const json& s) {
      const double b = s.value("bearing_deg", 0.0) * 3.14159265358979 / 180;
      const double d = s.value("distance_m", 1.0);
      return std::pair{d * std::cos(b), d * std::sin(b)};
    };
    for (const json& s : seen) {
      if (s.value("kind", "") != "person" || s.value("name", "").empty()) continue;
      const std::string who = s.value("name", "");
      if (std::find(known.begin(), known.end(), who) == known.end()) known.push_back(who);
      auto [x, y] = at(s);
      people.push_back({x, y, true});
    }
    int unknown = 0;
    for (const json& s : seen) {
      if (s.value("kind", "") != "person" || !s.value("name", "").empty()) continue;
      auto [x, y] = at(s);
      const bool same = std::any_of(people.begin(), people.end(), [&](const At& p) {
        return std::hypot(p.x - x, p.y - y) < 1.0;
      });
      people.push_back({x, y, false});
      if (!same) ++unknown;
    }
    return unknown;
  }

  void tell(const std::string& name_said, const std::string& message) {
    Wanted w = wanted(name_said);  // "my daughter" -> Anna
    if (!w.person) {
      if (w.mine) return say_relation_unknown(w.key);
      robot().say("I don't know anyone called " + capitalised(w.key) + ".");
      return;
    }
    std::string first;
    const std::optional<json> seen = last_seen(w);
    if (seen) first = seen->value("room", "");
    if (!seen && !knows_face(w.key)) {
      say_face_unknown(w);
      return;
    }
    if (first.empty()) {
      if (auto place = robot().place_find(w.key)) first = place->value("room", "");
    }
    robot().say("I'll tell " + w.key + ".");
    const Found found = search(w, first);
    if (!found.where) {
      say_not_found(w, found);
      return;
    }
    // Close enough to be heard: to the person's spot when the map has one in this room.
    if (auto place = robot().place_find(w.key)) {
      if (place->value("room", "") == found.where->value("room", "")) {
        try {
          robot().go_to(w.key);
        } catch (const marvin::Error& e) {
          if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
        }
      }
    }
    robot().say(w.key + ", " + message + ".");
  }

  void guard_on() {
    const json state = robot().guard(1);
    robot().say("OK, I'm guarding the house. I'll tell your carer if someone I don't know "
                "comes in.");
    robot().storage_set("guard_since", std::to_string(state.value("since_unix_ms", std::int64_t{0})));
  }

  void guard_off() {
    // "I'm home" with no guarding to stop is a greeting, not a request to check a face.
    if (!robot().guard(-1).value("on", false)) {
      robot().say("Welcome home!");
      return;
    }
    try {
      const json state = robot().guard(0);
      const std::string by = state.value("by", "");
      const int alerts = state.value("alerts", 0);
      std::string sentence = "Welcome back" + (by.empty() ? std::string() : ", " + by) +
                             ". I stopped guarding.";
      if (alerts > 0) {
        sentence += " Someone I don't know came while you were out: ask me who came.";
      }
      robot().say(sentence);
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_PERMISSION) throw;
      robot().say("I can only stop guarding for someone I know. Please let me see your face.");
    }
  }

  void who_came() {
    std::int64_t since = 0;
    if (auto stored = robot().storage_get("guard_since")) since = std::stoll(*stored);
    const json events = robot().events_list("intruder", since);
    if (events.empty()) {
      robot().say(since ? "Nobody came while you were out." : "Nobody came while I was guarding.");
      return;
    }
    const std::int64_t now = robot().now_ms();
    std::vector<std::string> parts;
    for (const json& e : events) {
      std::string m = e.value("message", "");
      // "Intruder alert: I see someone I don't know in the hall. Photo: ..." -> the middle
      const auto start = m.find("I see ");
      const auto stop = m.find(". Photo");
      std::string what = start == std::string::npos ? m : m.substr(start + 6, stop == std::string::npos ? std::string::npos : stop - start - 6);
      parts.push_back(what + ", " + ago(now - e.value("time_unix_ms", now)));
    }
    robot().say(std::string(events.size() == 1 ? "One visitor" : std::to_string(events.size()) + " alerts") +
                ": " + join_and(parts) + ". I saved a photo of each in my data folder.");
  }
};

}  // namespace

MARVIN_SKILL(FindingSkill, "finding")
