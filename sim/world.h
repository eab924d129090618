// The simulated home: the world file (format in README.md) and what it describes. A World
// holds the floor plan navigation sees (map) plus what only the simulator knows: clutter
// the plan does not show, objects and people with their photos, smart-home devices and
// the robot's start pose and dimensions.
#pragma once

#include <array>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "navigation/floor_map.h"

namespace marvin::sim {

// A world file that cannot be used. The message names the file, the element
// ("doors[2] \"kitchen door\"") and the field, and says what was expected.
class WorldError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Thing {
  std::string name;
  navigation::Vec2 at;
  std::string room;
  double elevation_m = 0;  // how high it sits (on a table: the table's height)
  double size_m = 0.1;     // its height in the picture; its width follows the photo
  std::vector<std::filesystem::path> photos;  // absolute paths
  // The part of the first photo the camera shows, in pixels {x, y, width, height};
  // width 0: the whole photo. Lets a world use one face of a group photo.
  std::array<int, 4> crop{0, 0, 0, 0};
};

struct Person : Thing {
  bool owner = false;  // the person who talks to the robot ("come here")
};

struct SmartDevice {
  std::string name, type, room;
  bool dimmable = false;
};

// A step down: the floor inside the box is `depth_m` lower (a sunken living room, the step
// down to a garden). Not on the map: only the downward sonar finds it; a robot whose
// centre goes over its edge falls.
struct Drop {
  std::string name;
  navigation::Box box;  // box.height unused
  double depth_m = 0.2;
};

struct RobotSpec {
  navigation::Pose start;
  double radius_m = 0.15, track_m = 0.25, max_speed_m_s = 0.4, accel_m_s2 = 1.0;
  double sonar_height_m = 0.25, camera_height_m = 0.35;
};

struct World {
  std::filesystem::path file;
  std::string name;
  double wall_height_m = 2.5;
  navigation::FloorMap map;
  std::vector<navigation::Furniture> clutter;  // solid, but not on the map
  std::vector<Drop> drops;                     // steps down, not on the map
  std::vector<Thing> objects;
  std::vector<Person> people;
  std::vector<SmartDevice> devices;
  RobotSpec robot;
  std::vector<std::string> room_colours;  // "#rrggbb" per map.rooms entry (floor)

  // Every solid side the sonar, the camera and collisions see: walls, furniture, clutter.
  std::vector<navigation::Segment> solid_segments() const;
};

inline constexpr int kWorldFormatVersion = 1;

// Reads and validates a world file. Throws WorldError.
World load_world(const std::filesystem::path& file);
// Same, from JSON text; `file` names it in messages and anchors relative photo paths.
World parse_world(const std::string& json_text, const std::filesystem::path& file);

// The default home: examples/worlds/home.json of this source tree.
std::filesystem::path default_world_file();

}  // namespace marvin::sim
