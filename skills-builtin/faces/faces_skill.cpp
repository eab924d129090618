// Built-in skill "faces": who is in front of the robot, and learning or forgetting faces.
//   "who is this?" / "who is in front of you?"
//        -> "That's Anna." / "I see Anna and someone I don't know." / "I don't see anyone."
//   "who is Anna?" / "tell me who Tom is" (a contact's name or alias: the interpreter
//        fills the slot only with one) -> "Anna is your daughter." from the contact book, not
//        the camera: a person asking has forgotten who Anna is, not whether she is here.
//        A name that is no contact leaves the slot empty and is answered as "who is this?".
//   "what do you see?" / "what's in front of you?"
//        -> the things and the people in view: "I see a cup, two chairs and Anna."
//   "do you see a phone?" / "is there a cup?" (the 80 COCO things by the names people use:
//        the list slot's values are core/vision/object_names.cpp's spoken names, checked
//        by vision_tests)  -> "Yes, I see two cups." / "No, I don't see a cup."
//   "this is Anna" / "remember this face as Anna" / "this is my daughter" (Anna, from the
//        contact book; a relation no contact has: "What is your neighbour's name?")
//        -> asks "Shall I remember this face as Anna?"; only a yes enrols (from 5 frames)
//   "forget Anna's face"     -> removes Anna and every embedding of her face
//   "forget my face"         -> the one known face in view, after "Shall I forget your face,
//                               Tom?" and a yes
//   "these are my keys"      -> learns the look of what is held up to the camera
//   "do you see my keys?"    -> "Yes, I see your keys." / "No, I don't see your keys."
// Consent: enrolment happens only after the spoken yes (the owner's: Marvin cannot yet tell
// voices apart) or through `marvin people enroll`; no photo is stored, only the numbers.
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include <marvin/skill.hpp>

#include "common/spoken_text.h"

namespace {

using marvin::builtin::join_and;
using marvin::builtin::lower;

using nlohmann::json;

constexpr std::uint32_t kEnrolFrames = 5;

// "anna's" -> "Anna"; "anna maria" -> "Anna Maria".
// "Anna's" -> "Anna"; an answer to "What name should I remember the face by?" may say more
// than the name: "my name is Anna", "I'm Anna", "it's Anna".
std::string person_name(std::string s) {
  for (const char* lead : {"my name is ", "my name's ", "i'm ", "i am ", "it's ", "it is ",
                           "this is ", "call me "}) {
    const std::string l = lead;
    if (s.size() > l.size() && lower(s.substr(0, l.size())) == l) s = s.substr(l.size());
  }
  while (!s.empty() && std::string_view(".!?,").find(s.back()) != std::string_view::npos) {
    s.pop_back();
  }
  if (s.size() > 2 && s.compare(s.size() - 2, 2, "'s") == 0) s.resize(s.size() - 2);
  return marvin::builtin::capitalised(s);
}

// "Anna", "someone I don't know", "two people I don't know".
std::vector<std::string> people_in(const json& seen) {
  std::vector<std::string> known;
  int unknown = 0;
  for (const json& f : seen.value("faces", json::array())) {
    const std::string name = f.value("name", "");
    if (name.empty()) ++unknown;
    else known.push_back(name);
  }
  static const char* kCounts[] = {"", "", "two", "three", "four", "five"};
  if (unknown == 1) known.push_back("someone I don't know");
  if (unknown > 1) {
    known.push_back((unknown < 6 ? std::string(kCounts[unknown]) : std::to_string(unknown)) +
                    " people I don't know");
  }
  return known;
}

std::string count_word(int n) {
  static const char* kCounts[] = {"", "a", "two", "three", "four", "five", "six", "seven",
                                  "eight", "nine", "ten"};
  return n <= 10 ? kCounts[n] : std::to_string(n);
}

// The plural of a label vision_look gives (the names people use: "phone", "knife", "glass").
std::string plural(const std::string& s) {
  auto ends = [&](const char* e) {
    const std::string t(e);
    return s.size() >= t.size() && s.compare(s.size() - t.size(), t.size(), t) == 0;
  };
  if (s == "person") return "people";
  if (s == "sheep" || s == "skis" || s == "scissors" || s == "broccoli") return s;
  if (ends("knife")) return s.substr(0, s.size() - 2) + "ves";
  if (ends("s") || ends("x") || ends("ch") || ends("sh")) return s + "es";
  return s + "s";
}

// "a cup", "an apple", "two chairs", in the order first seen (the detector's: most
// confident first). People are counted apart: a "person" the camera sees is only said when
// there are more of them than faces (someone seen from behind); faces say who.
std::vector<std::string> things_in(const json& seen) {
  std::vector<std::pair<std::string, int>> counts;
  int persons = 0;
  for (const json& o : seen.value("objects", json::array())) {
    const std::string label = o.value("label", "thing");
    if (label == "person") {
      ++persons;
      continue;
    }
    auto it = std::find_if(counts.begin(), counts.end(),
                           [&](const auto& c) { return c.first == label; });
    if (it == counts.end()) counts.emplace_back(label, 1);
    else ++it->second;
  }
  const int faces = static_cast<int>(seen.value("faces", json::array()).size());
  if (persons > faces) counts.emplace_back(faces == 0 ? "person" : "other person", persons - faces);
  std::vector<std::string> out;
  for (const auto& [label, n] : counts) {
    if (label == "other person") {
      out.push_back(n == 1 ? "someone else" : count_word(n) + " other people");
    } else if (n == 1) {
      const bool vowel = std::string("aeiou").find(label[0]) != std::string::npos;
      out.push_back((vowel ? "an " : "a ") + label);
    } else {
      out.push_back(count_word(n) + " " + plural(label));
    }
  }
  return out;
}

class FacesSkill : public marvin::Skill {
 public:
  using Skill::Skill;

  void handle(const marvin::Request& r) override {
    try {
      if (r.intent == "who") who(asks_about_me(r.utterance));
      else if (r.intent == "who_is") who_is(r.slots.value("person", ""));
      else if (r.intent == "what_do_you_see") what_do_you_see();
      else if (r.intent == "is_there") is_there(lower(r.slots.at("object").get<std::string>()));
      else if (r.intent == "enroll") introduce(r.slots.at("name").get<std::string>(), true);
      else if (r.intent == "forget") forget_said(r.slots.value("name", ""));
      else if (r.intent == "teach_object") introduce(r.slots.at("thing").get<std::string>(), false);
      else if (r.intent == "find_object") find_object(lower(r.slots.at("thing").get<std::string>()));
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      robot().log(MARVIN_LOG_WARNING, e.what());
      // The camera, or (learning with a camera that works) the store that keeps faces.
      robot().say(camera_works()
                      ? "Sorry, I can't learn anything new right now: I have nowhere to keep it."
                      : "Sorry, I can't see anything right now: my camera is not working.");
    }
  }

 private:
  // "who am I", "what's my name": the speaker is the one in front of the camera.
  static bool asks_about_me(const std::string& utterance) {
    // Not any "me": "who is in front of me" asks about someone else.
    static constexpr const char* kMe[] = {" know me ", " recognise me ", " recognize me ",
                                          " remember me "};
    const std::string u = " " + lower(utterance) + " ";
    return u.find(" i ") != std::string::npos || u.find(" am i") != std::string::npos ||
           u.find(" my name") != std::string::npos ||
           std::any_of(std::begin(kMe), std::end(kMe),
                       [&](const char* m) { return u.find(m) != std::string::npos; });
  }

  // `me`: said to the one asking ("You're Anna.").
  void who(bool me = false) {
    const json seen = robot().vision_look();
    const auto people = people_in(seen);
    if (people.empty()) {
      robot().say(me ? "I can't see you. Please come and stand in front of me."
                     : "I don't see anyone.");
    } else if (people.size() == 1 && people[0] != "someone I don't know" &&
               people[0].find("people") == std::string::npos) {
      robot().say((me ? "You're " : "That's ") + people[0] + ".");
    } else if (people.size() == 1 && people[0] == "someone I don't know") {
      robot().say(me ? "I don't know your face yet. To introduce yourself, say \"remember my "
                       "face\"."
                     : "That's someone I don't know.");
    } else {
      robot().say("I see " + join_and(people) + ".");
    }
  }

  void who_is(const std::string& name) {
    const json found = name.empty() ? json::array() : robot().contacts_find(name);
    if (found.empty()) return who();
    const json& contact = found[0];
    const std::string full = contact.value("name", name);
    const std::string relation = contact.value("relation", "");
    const std::string role = relation.empty() ? "one of your contacts" : "your " + relation;
    // "my doctor": "Your doctor is Doctor Brown."
    if (lower(name).rfind("my ", 0) == 0) {
      return robot().say("Your " + name.substr(3) + " is " + full + ".");
    }
    // "Annie" is an alias of Anna Schmidt: "Annie is Anna Schmidt, your daughter."
    robot().say(lower(full) == lower(name) ? full + " is " + role + "."
                                           : name + " is " + full + ", " + role + ".");
  }

  void what_do_you_see() {
    const json seen = robot().vision_look();
    std::vector<std::string> things = things_in(seen);
    for (const std::string& p : people_in(seen)) things.push_back(p);
    robot().say(things.empty() ? "I don't see anything I know." : "I see " + join_and(things) + ".");
  }

  void is_there(const std::string& thing) {
    const json seen = robot().vision_look();
    int n = 0;
    for (const json& o : seen.value("objects", json::array())) n += o.value("label", "") == thing;
    if (thing == "person") n = std::max(n, static_cast<int>(seen.value("faces", json::array()).size()));
    const bool vowel = !thing.empty() && std::string("aeiou").find(thing[0]) != std::string::npos;
    const std::string one = (vowel ? "an " : "a ") + thing;
    if (n == 0) robot().say("No, I don't see " + one + ".");
    else robot().say("Yes, I see " + (n == 1 ? one : count_word(n) + " " + plural(thing)) + ".");
  }

  // "this is Anna", "this is my daughter Anna", "this is my neighbour", "these are my keys":
  // a person is enrolled (by their name, asked for when only the relation was said), a
  // thing is learnt. `person`: the request was to remember a face.
  void introduce(const std::string& said, bool person) {
    const std::vector<std::string> w = person_words(said);
    const bool relation = !w.empty() && is_relation(w[0]);
    const std::vector<std::string> rest(relation ? w.begin() + 1 : w.begin(), w.end());
    std::string name = contact_named(rest);
    if (name.empty() && relation) {
      name = rest.empty() ? contact_named({w[0]}) : person_name(marvin::builtin::join_words(rest));
      if (name.empty()) {
        name = person_name(robot().ask("What is your " + w[0] + "'s name?"));
        if (name.empty()) return robot().say("OK, I won't remember the face.");
      }
    }
    if (name.empty() && !person) return teach_object(lower(said));
    enroll(name.empty() ? person_name(said) : name);
  }

  // "my daughter's" -> {"daughter"}: the words that may name a person, lower case.
  static std::vector<std::string> person_words(const std::string& said) {
    std::vector<std::string> w = marvin::builtin::words_in(said);  // lower case
    if (!w.empty() && (w[0] == "my" || w[0] == "our")) w.erase(w.begin());
    if (!w.empty() && w.back().size() > 2 && w.back().ends_with("'s")) {
      w.back().resize(w.back().size() - 2);
    }
    return w;
  }

  // The one contact those words name ("daughter", "anna"), else "".
  std::string contact_named(const std::vector<std::string>& words) {
    if (words.empty()) return "";
    const json found = robot().contacts_find(marvin::builtin::join_words(words));
    return found.size() == 1 ? found[0].value("name", "") : "";
  }

  bool camera_works() {
    try {
      robot().vision_look();
      return true;
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
      return false;
    }
  }

  // Words for the people in one's life: "my daughter Anna" is a person, "my keys" a thing.
  static bool is_relation(const std::string& word) {
    static const std::vector<std::string> kRelations = {
        "daughter", "son",      "wife",     "husband",  "partner", "mother",     "mum",
        "mom",      "father",   "dad",      "sister",   "brother", "grandson",   "granddaughter",
        "grandchild", "niece",  "nephew",   "aunt",     "uncle",   "cousin",     "friend",
        "neighbour", "neighbor", "carer",   "caregiver", "nurse",  "doctor",     "cleaner"};
    return std::find(kRelations.begin(), kRelations.end(), word) != kRelations.end();
  }

  void enroll(const std::string& name) {
    // Asked only with a face in view: "Shall I remember this face?" with nobody there asks
    // the owner to consent to nothing. (Without a camera the enrolment says why.)
    try {
      const json faces = robot().vision_look().value("faces", json::array());
      if (faces.empty()) {
        robot().say("I don't see a face. Please look at me and try again.");
        return;
      }
      if (faces.size() > 1) {
        robot().say("I see more than one face. Please let " + name +
                    " stand alone in front of me.");
        return;
      }
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_UNAVAILABLE) throw;
    }
    const std::string answer =
        lower(robot().ask("Shall I remember this face as " + name + "?"));
    if (!marvin::builtin::said_yes(answer)) {
      robot().say("OK, I won't remember it.");
      return;
    }
    try {
      robot().vision_enroll_face(name, kEnrolFrames);
    } catch (const marvin::Error& e) {
      if (e.status() == MARVIN_ERR_NOT_FOUND) {
        robot().say("I don't see a face. Please look at me and try again.");
        return;
      }
      if (e.status() == MARVIN_ERR_INVALID) {
        robot().say("I see more than one face. Please let " + name + " stand alone in front of me.");
        return;
      }
      throw;
    }
    robot().say("Nice to meet you, " + name + ". I'll remember your face.");
  }

  void teach_object(const std::string& thing) {
    try {
      robot().vision_teach_object(thing);
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_INVALID) throw;
      robot().say("I can't make out your " + thing + ". Please hold them closer, in front of me.");
      return;
    }
    robot().say("OK, I'll remember what your " + thing + " look like.");
  }

  void find_object(const std::string& thing) {
    const auto found = robot().vision_find_object(thing);
    if (!found) {
      robot().say("I don't know what your " + thing + " look like. Show them to me and say "
                  "\"these are my " + thing + "\".");
    } else if (found->value("found", false)) {
      robot().say("Yes, I see your " + thing + ".");
    } else {
      robot().say("No, I don't see your " + thing + ".");
    }
  }

  // "forget my daughter's face": the contact's name; "forget my face" (no name): the one
  // known face in view, after a yes, since the name was not said.
  void forget_said(const std::string& said) {
    if (!said.empty()) {
      const std::string contact = contact_named(person_words(said));
      return forget(contact.empty() ? person_name(said) : contact);
    }
    const std::vector<std::string> people = people_in(robot().vision_look());
    if (people.empty()) {
      return robot().say("I don't see anyone. Please look at me, or tell me whose face to forget.");
    }
    if (people.size() > 1 || people[0].find("people") != std::string::npos) {
      return robot().say("I see more than one person. Please tell me whose face to forget.");
    }
    if (people[0] == "someone I don't know") {
      return robot().say("I don't know your face, so there is nothing to forget.");
    }
    const std::string answer = lower(robot().ask("Shall I forget your face, " + people[0] + "?"));
    if (!marvin::builtin::said_yes(answer)) {
      return robot().say("OK, I'll keep it.");
    }
    forget(people[0]);
  }

  void forget(const std::string& name) {
    try {
      robot().vision_forget_face(name);
    } catch (const marvin::Error& e) {
      if (e.status() != MARVIN_ERR_NOT_FOUND) throw;
      robot().say("I don't know " + name + "'s face.");
      return;
    }
    robot().say("OK, I forgot " + name + "'s face.");
  }
};

}  // namespace

MARVIN_SKILL(FacesSkill, "faces")
