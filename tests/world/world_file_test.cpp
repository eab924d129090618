// The world file: the default home loads; malformed files give errors naming the element
// and the field.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "sim/world.h"

using marvin::sim::parse_world;
using marvin::sim::WorldError;

namespace {

// A one-room world with `extra` spliced in before the robot.
std::string world_with(const std::string& extra) {
  return R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[4,0],[4,3],[0,3]]},
              {"name": "kitchen", "outline": [[4,0],[8,0],[8,3],[4,3]]}],
    )" + extra +
         R"(
    "robot": {"start": [1, 1]}})";
}

std::string error_of(const std::string& text) {
  try {
    parse_world(text, "/tmp/w.json");
  } catch (const WorldError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("the default home loads with its rooms, doors, places and devices") {
  marvin::sim::World w = marvin::sim::load_world(marvin::sim::default_world_file());
  REQUIRE(w.map.rooms.size() == 5);
  CHECK(w.map.find("the kitchen")->name == "kitchen");
  CHECK(w.map.find("sofa")->name == "the sofa");
  CHECK(w.map.find("anna")->kind == marvin::navigation::Target::Kind::kPerson);
  // Other words for a room the map has; none for one it lacks.
  CHECK(w.map.find("the toilet")->name == "bathroom");
  CHECK(w.map.find("The Lounge")->name == "living room");
  CHECK(w.map.find("hallway")->name == "hall");
  CHECK(w.map.find("the kitchenette")->name == "kitchen");
  CHECK_FALSE(w.map.find("the garage").has_value());
  CHECK(w.devices.size() == 9);
  CHECK(w.devices.at(8).name == "bedroom thermostat");
  CHECK(w.devices.at(8).type == "thermostat");
  CHECK(w.devices.at(1).name == "living room lamp");
  CHECK(w.devices.at(1).dimmable);
  CHECK(w.map.room_at(w.robot.start.position())->name == "hall");
  // Open doors are gaps in the wall: nothing solid at the kitchen door's middle.
  for (const auto& s : w.map.walls)
    CHECK(marvin::navigation::point_segment_distance({6, 2}, s.a, s.b) > 0.4);
}

TEST_CASE("a valid small world parses; a door cuts its wall") {
  auto w = parse_world(
      world_with(
          R"("doors": [{"name": "kitchen door", "at": [4, 1.5], "rooms": ["hall", "kitchen"]}],)"),
      "/tmp/w.json");
  CHECK(w.map.doors.size() == 1);
  CHECK(std::min(w.map.doors[0].a.y, w.map.doors[0].b.y) == doctest::Approx(1.05));
  // No bathroom here: "the toilet" is no room (not the hall, not the nearest).
  CHECK_FALSE(w.map.find("the toilet").has_value());
  CHECK(w.map.find("hallway")->name == "hall");
}

TEST_CASE("malformed world files name the element and the field") {
  CHECK(error_of("{").find("/tmp/w.json: not valid JSON") == 0);
  CHECK(error_of(R"({"format": "marvin-world", "version": 2})") ==
        "/tmp/w.json: 'version' must be 1 (this Marvin reads world format version 1)");
  CHECK(error_of(world_with(
            R"("doors": [{"name": "back door", "at": [2, 1.5], "rooms": ["hall"]}],)")) ==
        "/tmp/w.json: doors[0] \"back door\": 'at' [2, 1.5] is not on a wall (the nearest wall is "
        "1.5 m away)");
  CHECK(error_of(
            world_with(R"("places": [{"name": "the sink", "at": [5, 1], "room": "kitchn"}],)")) ==
        "/tmp/w.json: places[0] \"the sink\": 'room' \"kitchn\" is not a room of this world "
        "(rooms: hall, kitchen)");
  CHECK(
      error_of(world_with(
          R"("objects": [{"name": "keys", "at": [4.01, 1], "room": "kitchen", "photo": "k.jpg"}],)")) ==
      "/tmp/w.json: objects[0] \"keys\": 'at' [4.01, 1] is inside a wall");
  CHECK(error_of(world_with(
            R"("objects": [{"name": "keys", "at": [5, 1], "room": "hall", "photo": "k.jpg"}],)")) ==
        "/tmp/w.json: objects[0] \"keys\": 'at' [5, 1] is in the kitchen, not the hall");
  CHECK(
      error_of(world_with(R"("furniture": [{"name": "table", "min": [3.5, 1], "max": [4.5, 2]}],)"))
          .find("/tmp/w.json: furniture[0] \"table\": the box from [3.5, 1] to [4.5, 2] is inside "
                "a wall") == 0);
  CHECK(error_of(
            world_with(R"("devices": [{"name": "lamp", "type": "toaster", "room": "hall"}],)")) ==
        "/tmp/w.json: devices[0] \"lamp\": 'type' \"toaster\" must be \"light\", \"fan\", "
        "\"switch\" or \"thermostat\"");
  CHECK(error_of(world_with(
            R"("devices": [{"name": "lamp", "type": "light", "room": "hall", "temperature": 20}],)")) ==
        "/tmp/w.json: devices[0] \"lamp\": 'temperature' must be a number, on a thermostat (the "
        "room's, in degrees Celsius)");
  CHECK(
      error_of(world_with(
          R"("furniture": [{"name": "tv", "min": [1, 1], "max": [2, 1.3], "screen": "yes"}],)")) ==
      "/tmp/w.json: furniture[0] \"tv\": 'screen' must be true or false");
  CHECK(
      parse_world(
          world_with(
              R"("furniture": [{"name": "tv", "min": [1, 2], "max": [2, 2.3], "screen": true}],)"),
          "/tmp/w.json")
          .map.furniture.at(0)
          .screen);
  CHECK(error_of(world_with(R"("people": [{"name": "Tom", "at": [1, 2], "room": "hall"}],)")) ==
        "/tmp/w.json: people[0] \"Tom\": 'photo' (or 'photos') is missing: the camera shows it");
  CHECK(error_of(R"({"format": "marvin-world", "version": 1,
    "rooms": [{"name": "hall", "outline": [[0,0],[4,0],[4,3],[0,3]]}],
    "robot": {"start": [0.05, 1]}})") == "/tmp/w.json: robot: 'start' [0.05, 1] is inside a wall");
}

TEST_CASE("a world file that cannot be read names the file") {
  CHECK_THROWS_WITH_AS(marvin::sim::load_world("/nonexistent/w.json"),
                       "/nonexistent/w.json: cannot open the world file", WorldError);
}
