// What the robot knows of its home: walls (with the open doors cut out), furniture, named
// rooms, doors, places and where people were last seen. Built from a world file by the
// simulator (sim/world.h), or by hand for the real robot; navigation never reads the
// simulator's world itself.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "navigation/geometry.h"

namespace marvin::navigation {

struct Room {
  std::string name;           // "kitchen"
  std::vector<Vec2> outline;  // polygon, metres
  Vec2 spot;                  // where "go to the kitchen" ends
};

struct Door {
  std::string name;                // "kitchen door"
  Vec2 a, b;                       // the opening's two ends (on the wall)
  std::vector<std::string> rooms;  // the rooms it joins (one for an outside door)
  bool open = true;
};

// A named spot: a place ("the sofa") or a person's last known position ("Anna").
struct Place {
  std::string name;
  Vec2 at;
  std::string room;
};

struct Furniture {
  std::string name;
  Box box;
  // A TV or monitor stands here: a face seen at it is a picture, not a visitor (guard mode).
  bool screen = false;
};

// What a name the user said refers to.
struct Target {
  enum class Kind { kRoom, kPlace, kPerson } kind = Kind::kRoom;
  std::string name;  // as the map spells it
  Vec2 at;
  std::string room;
};

struct FloorMap {
  std::vector<Segment> walls;  // solid wall pieces; open doors are gaps
  std::vector<Furniture> furniture;
  std::vector<Room> rooms;
  std::vector<Door> doors;
  std::vector<Place> places;
  std::vector<Place> people;
  std::string owner;  // the person "me" means ("come here"); "" if unknown

  // The room whose outline holds p, or nullptr (outside, or exactly in a doorway).
  const Room* room_at(Vec2 p) const;
  // A room, place or person by name: case and a leading "the " do not matter
  // ("The Kitchen" finds room "kitchen", "sofa" finds place "the sofa"). Rooms first,
  // then places, then people; "me" is the owner; last, another word for a room the map has
  // ("the toilet" is the bathroom, "the lounge" the living room: room_synonyms()).
  std::optional<Target> find(std::string_view name) const;
  // The smallest axis-aligned box holding every wall and room.
  Box bounds() const;
};

// Lower case, single spaces, without a leading "the ", "my " or "a ".
std::string normalise_name(std::string_view name);

// Words people use for a room -> the room's usual name: {"toilet", "bathroom"}, ...
const std::vector<std::pair<std::string, std::string>>& room_synonyms();

}  // namespace marvin::navigation
