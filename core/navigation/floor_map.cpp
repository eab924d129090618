#include "navigation/floor_map.h"

#include <algorithm>
#include <cctype>

namespace marvin::navigation {

std::string normalise_name(std::string_view name) {
  std::string out;
  for (char c : name) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  for (std::string_view article : {"the ", "my ", "a "}) {
    if (out.rfind(article, 0) == 0) {
      out.erase(0, article.size());
      break;
    }
  }
  return out;
}

const Room* FloorMap::room_at(Vec2 p) const {
  for (const Room& r : rooms) {
    if (polygon_contains(r.outline, p)) return &r;
  }
  return nullptr;
}

std::optional<Target> FloorMap::find(std::string_view name) const {
  std::string want = normalise_name(name);
  if (want == "me" && !owner.empty()) want = normalise_name(owner);
  for (const Room& r : rooms) {
    if (normalise_name(r.name) == want) return Target{Target::Kind::kRoom, r.name, r.spot, r.name};
  }
  for (const Place& p : places) {
    if (normalise_name(p.name) == want) return Target{Target::Kind::kPlace, p.name, p.at, p.room};
  }
  for (const Place& p : people) {
    if (normalise_name(p.name) == want) return Target{Target::Kind::kPerson, p.name, p.at, p.room};
  }
  // Other words for a room ("the toilet" is the bathroom), when no room or place has it.
  for (const auto& [word, room_name] : room_synonyms()) {
    if (word != want) continue;
    for (const Room& r : rooms) {
      if (normalise_name(r.name) == room_name) {
        return Target{Target::Kind::kRoom, r.name, r.spot, r.name};
      }
    }
  }
  return std::nullopt;
}

const std::vector<std::pair<std::string, std::string>>& room_synonyms() {
  static const std::vector<std::pair<std::string, std::string>> kSynonyms = {
      {"toilet", "bathroom"},      {"loo", "bathroom"},         {"lavatory", "bathroom"},
      {"wc", "bathroom"},          {"restroom", "bathroom"},    {"washroom", "bathroom"},
      {"lounge", "living room"},   {"sitting room", "living room"}, {"front room", "living room"},
      {"living-room", "living room"}, {"hallway", "hall"},      {"corridor", "hall"},
      {"bed room", "bedroom"},     {"kitchenette", "kitchen"}};
  return kSynonyms;
}

Box FloorMap::bounds() const {
  Box b{{1e9, 1e9}, {-1e9, -1e9}, 0};
  auto add = [&](Vec2 p) {
    b.min.x = std::min(b.min.x, p.x);
    b.min.y = std::min(b.min.y, p.y);
    b.max.x = std::max(b.max.x, p.x);
    b.max.y = std::max(b.max.y, p.y);
  };
  for (const Segment& s : walls) {
    add(s.a);
    add(s.b);
  }
  for (const Room& r : rooms) {
    for (Vec2 p : r.outline) add(p);
  }
  if (b.min.x > b.max.x) return Box{{0, 0}, {1, 1}, 0};
  return b;
}

}  // namespace marvin::navigation
