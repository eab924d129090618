#include "sim/world.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace marvin::sim {
namespace {

using navigation::Vec2;
using nlohmann::json;

// Builds messages: "<file>: <element>: <what>".
struct Where {
  std::string file;
  std::string element;  // "doors[2] \"kitchen door\""
  [[noreturn]] void fail(const std::string& what) const {
    throw WorldError(file + ": " + (element.empty() ? "" : element + ": ") + what);
  }
};

std::string fmt(Vec2 p) {
  std::ostringstream out;
  out << "[" << p.x << ", " << p.y << "]";
  return out.str();
}

Where element(const std::string& file, const char* list, std::size_t i, const json& j) {
  std::string e = std::string(list) + "[" + std::to_string(i) + "]";
  if (j.is_object() && j.contains("name") && j["name"].is_string())
    e += " \"" + j["name"].get<std::string>() + "\"";
  return {file, e};
}

const json& field(const json& j, const char* key, const Where& w) {
  if (!j.is_object()) w.fail("must be a JSON object");
  if (!j.contains(key)) w.fail(std::string("'") + key + "' is missing");
  return j[key];
}

std::string text(const json& j, const char* key, const Where& w) {
  const json& v = field(j, key, w);
  if (!v.is_string() || v.get<std::string>().empty())
    w.fail(std::string("'") + key + "' must be a non-empty string");
  return v.get<std::string>();
}

double number(const json& j, const char* key, double fallback, const Where& w, double lo = 0,
              double hi = 1e6) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) w.fail(std::string("'") + key + "' must be a number");
  double v = j[key].get<double>();
  if (v < lo || v > hi) {
    std::ostringstream out;
    out << "'" << key << "' is " << v << ", expected " << lo << " to " << hi;
    w.fail(out.str());
  }
  return v;
}

Vec2 point_of(const json& v, const std::string& key, const Where& w) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    w.fail("'" + key + "' must be [x, y] in metres");
  return {v[0].get<double>(), v[1].get<double>()};
}
Vec2 point(const json& j, const char* key, const Where& w) {
  return point_of(field(j, key, w), key, w);
}

const json& list(const json& root, const char* key, const std::string& file) {
  static const json empty = json::array();
  if (!root.contains(key)) return empty;
  if (!root[key].is_array())
    throw WorldError(file + ": '" + std::string(key) + "' must be an array");
  return root[key];
}

std::string room_names(const navigation::FloorMap& map) {
  std::string out;
  for (const auto& r : map.rooms) out += (out.empty() ? "" : ", ") + r.name;
  return out;
}

// The room named `key`, which must exist; "" when the field is absent and optional.
std::string room_field(const json& j, const char* key, const navigation::FloorMap& map,
                       const Where& w, bool required) {
  if (!j.contains(key) && !required) return "";
  std::string name = text(j, key, w);
  for (const auto& r : map.rooms) {
    if (r.name == name) return name;
  }
  w.fail(std::string("'") + key + "' \"" + name +
         "\" is not a room of this world (rooms: " + room_names(map) + ")");
}

double nearest_wall(const std::vector<navigation::Segment>& walls, Vec2 p) {
  double best = 1e18;
  for (const auto& s : walls)
    best = std::min(best, navigation::point_segment_distance(p, s.a, s.b));
  return best;
}

// Checks a point lies in the named room (when given) and not in a wall.
void check_spot(const World& world, const std::vector<navigation::Segment>& walls, Vec2 p,
                const std::string& room, double clearance, const Where& w, const char* key) {
  if (nearest_wall(walls, p) < clearance)
    w.fail(std::string("'") + key + "' " + fmt(p) + " is inside a wall");
  const navigation::Room* in = world.map.room_at(p);
  if (!in) w.fail(std::string("'") + key + "' " + fmt(p) + " is outside every room");
  if (!room.empty() && in->name != room)
    w.fail(std::string("'") + key + "' " + fmt(p) + " is in the " + in->name + ", not the " + room);
}

std::vector<std::filesystem::path> photos(const json& j, const std::filesystem::path& base,
                                          const Where& w) {
  std::vector<std::filesystem::path> out;
  auto add = [&](const json& v) {
    if (!v.is_string()) w.fail("'photos' must be an array of file names");
    std::filesystem::path p = base / v.get<std::string>();
    out.push_back(p);
  };
  if (j.contains("photo")) add(j["photo"]);
  if (j.contains("photos")) {
    if (!j["photos"].is_array()) w.fail("'photos' must be an array of file names");
    for (const auto& v : j["photos"]) add(v);
  }
  return out;
}

}  // namespace

std::vector<navigation::Segment> World::solid_segments() const {
  std::vector<navigation::Segment> out = map.walls;
  navigation::Segment s[4];
  for (const auto* group : {&map.furniture, &clutter}) {
    for (const auto& f : *group) {
      f.box.sides(s);
      out.insert(out.end(), s, s + 4);
    }
  }
  return out;
}

World load_world(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw WorldError(file.string() + ": cannot open the world file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_world(buffer.str(), file);
}

World parse_world(const std::string& json_text, const std::filesystem::path& file_path) {
  const std::string file = file_path.string();
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw WorldError(file + ": not valid JSON: " + e.what());
  }
  Where top{file, ""};
  if (!root.is_object()) top.fail("a world must be a JSON object");
  if (text(root, "format", top) != "marvin-world") top.fail("'format' must be \"marvin-world\"");
  const json& version = field(root, "version", top);
  if (!version.is_number_integer() || version.get<int>() != kWorldFormatVersion)
    top.fail("'version' must be " + std::to_string(kWorldFormatVersion) +
             " (this Marvin reads world format version 1)");
  World world;
  world.file = file_path;
  world.name = root.value("name", file_path.stem().string());
  world.wall_height_m = number(root, "wall_height_m", 2.5, top, 1, 10);
  const std::filesystem::path base = file_path.parent_path();

  // Rooms: outlines; their edges are the walls (shared edges are walls of both rooms).
  std::vector<navigation::Segment> walls;
  const json& rooms = list(root, "rooms", file);
  if (rooms.empty()) top.fail("'rooms' must list at least one room");
  for (std::size_t i = 0; i < rooms.size(); ++i) {
    Where w = element(file, "rooms", i, rooms[i]);
    navigation::Room room;
    room.name = text(rooms[i], "name", w);
    for (const auto& r : world.map.rooms) {
      if (r.name == room.name) w.fail("'name' \"" + room.name + "\" is used by another room");
    }
    const json& outline = field(rooms[i], "outline", w);
    if (!outline.is_array() || outline.size() < 3)
      w.fail("'outline' must be an array of at least 3 points [x, y]");
    for (const auto& p : outline) room.outline.push_back(point_of(p, "outline", w));
    for (std::size_t k = 0; k < room.outline.size(); ++k) {
      walls.push_back(
          {room.outline[k], room.outline[(k + 1) % room.outline.size()], world.wall_height_m});
    }
    room.spot = rooms[i].contains("spot") ? point(rooms[i], "spot", w)
                                          : navigation::polygon_centroid(room.outline);
    if (!navigation::polygon_contains(room.outline, room.spot))
      w.fail("'spot' " + fmt(room.spot) + " is not inside the room's outline");
    world.room_colours.push_back(rooms[i].value("floor_colour", std::string("#d8cfc0")));
    world.map.rooms.push_back(std::move(room));
  }
  const json& extra_walls = list(root, "walls", file);
  for (std::size_t i = 0; i < extra_walls.size(); ++i) {
    Where w = element(file, "walls", i, extra_walls[i]);
    walls.push_back({point(extra_walls[i], "from", w), point(extra_walls[i], "to", w),
                     number(extra_walls[i], "height_m", world.wall_height_m, w, 0.05, 10)});
  }

  // Doors cut their opening out of every wall they lie on.
  const json& doors = list(root, "doors", file);
  for (std::size_t i = 0; i < doors.size(); ++i) {
    Where w = element(file, "doors", i, doors[i]);
    navigation::Door door;
    door.name = text(doors[i], "name", w);
    const Vec2 at = point(doors[i], "at", w);
    const double width = number(doors[i], "width_m", 0.9, w, 0.5, 3);
    door.open = doors[i].value("open", true);
    const json& joined = field(doors[i], "rooms", w);
    if (!joined.is_array() || joined.empty() || joined.size() > 2)
      w.fail("'rooms' must name the one or two rooms the door joins");
    for (std::size_t k = 0; k < joined.size(); ++k) {
      json one = {{"room", joined[k]}};
      door.rooms.push_back(room_field(
          one, "room", world.map, {file, w.element + " rooms[" + std::to_string(k) + "]"}, true));
    }
    std::vector<navigation::Segment> cut;
    bool on_wall = false;
    for (const auto& s : walls) {
      const double len = navigation::distance(s.a, s.b);
      if (len < 1e-9 || navigation::point_segment_distance(at, s.a, s.b) > 0.05) {
        cut.push_back(s);
        continue;
      }
      const navigation::Vec2 dir = (s.b - s.a) * (1.0 / len);
      const double t = navigation::dot(at - s.a, dir);
      if (t - width / 2 < -1e-6 || t + width / 2 > len + 1e-6)
        w.fail("the opening (" + std::to_string(width) + " m at " + fmt(at) +
               ") does not fit on the wall from " + fmt(s.a) + " to " + fmt(s.b));
      on_wall = true;
      door.a = s.a + dir * (t - width / 2);
      door.b = s.a + dir * (t + width / 2);
      if (!door.open) {
        cut.push_back(s);
        continue;
      }
      if (t - width / 2 > 1e-6) cut.push_back({s.a, door.a, s.height});
      if (t + width / 2 < len - 1e-6) cut.push_back({door.b, s.b, s.height});
    }
    if (!on_wall) {
      std::ostringstream out;
      out << "'at' " << fmt(at) << " is not on a wall (the nearest wall is "
          << nearest_wall(walls, at) << " m away)";
      w.fail(out.str());
    }
    walls = std::move(cut);
    world.map.doors.push_back(std::move(door));
  }
  world.map.walls = walls;

  auto boxes = [&](const char* key, std::vector<navigation::Furniture>& out) {
    const json& items = list(root, key, file);
    for (std::size_t i = 0; i < items.size(); ++i) {
      Where w = element(file, key, i, items[i]);
      navigation::Furniture f;
      f.name = text(items[i], "name", w);
      f.box.min = point(items[i], "min", w);
      f.box.max = point(items[i], "max", w);
      f.box.height = number(items[i], "height_m", 0.5, w, 0.01, 10);
      if (f.box.min.x >= f.box.max.x || f.box.min.y >= f.box.max.y)
        w.fail("'min' " + fmt(f.box.min) + " must be below and left of 'max' " + fmt(f.box.max));
      if (items[i].contains("screen") && !items[i]["screen"].is_boolean())
        w.fail("'screen' must be true or false");
      f.screen = items[i].value("screen", false);
      std::string room = room_field(items[i], "room", world.map, w, false);
      for (const auto& s : walls) {
        navigation::Segment sides[4];
        f.box.sides(sides);
        for (const auto& side : sides) {
          if (navigation::segments_intersect(side.a, side.b, s.a, s.b))
            w.fail("the box from " + fmt(f.box.min) + " to " + fmt(f.box.max) +
                   " is inside a wall (it crosses the wall from " + fmt(s.a) + " to " + fmt(s.b) +
                   ")");
        }
      }
      const Vec2 centre = (f.box.min + f.box.max) * 0.5;
      const navigation::Room* in = world.map.room_at(centre);
      if (!in)
        w.fail("the box from " + fmt(f.box.min) + " to " + fmt(f.box.max) +
               " is outside every room");
      if (!room.empty() && in->name != room)
        w.fail("the box is in the " + in->name + ", not the " + room);
      out.push_back(std::move(f));
    }
  };
  boxes("furniture", world.map.furniture);
  boxes("clutter", world.clutter);

  // Steps down may span a doorway (cross walls); their centre must be in a room.
  const json& drops = list(root, "drops", file);
  for (std::size_t i = 0; i < drops.size(); ++i) {
    Where w = element(file, "drops", i, drops[i]);
    Drop d;
    d.name = text(drops[i], "name", w);
    d.box.min = point(drops[i], "min", w);
    d.box.max = point(drops[i], "max", w);
    d.depth_m = number(drops[i], "depth_m", 0.2, w, 0.05, 3);
    if (d.box.min.x >= d.box.max.x || d.box.min.y >= d.box.max.y)
      w.fail("'min' " + fmt(d.box.min) + " must be below and left of 'max' " + fmt(d.box.max));
    if (!world.map.room_at((d.box.min + d.box.max) * 0.5))
      w.fail("the step from " + fmt(d.box.min) + " to " + fmt(d.box.max) +
             " is outside every room");
    world.drops.push_back(std::move(d));
  }

  const json& places = list(root, "places", file);
  for (std::size_t i = 0; i < places.size(); ++i) {
    Where w = element(file, "places", i, places[i]);
    navigation::Place p;
    p.name = text(places[i], "name", w);
    p.at = point(places[i], "at", w);
    p.room = room_field(places[i], "room", world.map, w, true);
    check_spot(world, walls, p.at, p.room, 0.05, w, "at");
    world.map.places.push_back(std::move(p));
  }

  auto thing = [&](const json& j, const Where& w, Thing& t, double default_size) {
    t.name = text(j, "name", w);
    t.at = point(j, "at", w);
    t.room = room_field(j, "room", world.map, w, true);
    t.elevation_m = number(j, "elevation_m", 0, w, 0, 3);
    t.size_m = number(j, "size_m", default_size, w, 0.01, 2.5);
    t.photos = photos(j, base, w);
    if (t.photos.empty()) w.fail("'photo' (or 'photos') is missing: the camera shows it");
    if (j.contains("crop")) {
      const json& c = j["crop"];
      bool ok = c.is_array() && c.size() == 4;
      for (std::size_t k = 0; ok && k < 4; ++k)
        ok = c[k].is_number_integer() && c[k].get<int>() >= 0;
      if (!ok || c[2].get<int>() == 0 || c[3].get<int>() == 0)
        w.fail(
            "'crop' must be [x, y, width, height] in pixels (whole numbers, width and height > 0)");
      for (std::size_t k = 0; k < 4; ++k) t.crop[k] = c[k].get<int>();
    }
    check_spot(world, walls, t.at, t.room, 0.03, w, "at");
  };
  const json& objects = list(root, "objects", file);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    Where w = element(file, "objects", i, objects[i]);
    Thing t;
    thing(objects[i], w, t, 0.15);
    world.objects.push_back(std::move(t));
  }
  const json& people = list(root, "people", file);
  for (std::size_t i = 0; i < people.size(); ++i) {
    Where w = element(file, "people", i, people[i]);
    Person p;
    thing(people[i], w, p, 1.6);
    p.owner = people[i].value("owner", false);
    if (p.owner) world.map.owner = p.name;
    world.map.people.push_back({p.name, p.at, p.room});
    world.people.push_back(std::move(p));
  }

  const json& devices = list(root, "devices", file);
  for (std::size_t i = 0; i < devices.size(); ++i) {
    Where w = element(file, "devices", i, devices[i]);
    SmartDevice d;
    d.name = text(devices[i], "name", w);
    d.type = text(devices[i], "type", w);
    if (d.type != "light" && d.type != "fan" && d.type != "switch" && d.type != "thermostat")
      w.fail("'type' \"" + d.type + "\" must be \"light\", \"fan\", \"switch\" or \"thermostat\"");
    if (devices[i].contains("temperature") &&
        (d.type != "thermostat" || !devices[i]["temperature"].is_number()))
      w.fail("'temperature' must be a number, on a thermostat (the room's, in degrees Celsius)");
    d.room = room_field(devices[i], "room", world.map, w, true);
    if (devices[i].contains("dimmable") && !devices[i]["dimmable"].is_boolean())
      w.fail("'dimmable' must be true or false");
    d.dimmable = devices[i].value("dimmable", false);
    world.devices.push_back(std::move(d));
  }

  Where rw{file, "robot"};
  const json& robot = field(root, "robot", top);
  const Vec2 start = point(robot, "start", rw);
  world.robot.start = {start.x, start.y,
                       number(robot, "heading_deg", 0, rw, -360, 360) * navigation::kPi / 180};
  world.robot.radius_m = number(robot, "radius_m", 0.15, rw, 0.05, 1);
  world.robot.track_m = number(robot, "track_m", 0.25, rw, 0.05, 1);
  world.robot.max_speed_m_s = number(robot, "max_speed_m_s", 0.4, rw, 0.01, 3);
  world.robot.accel_m_s2 = number(robot, "accel_m_s2", 1.0, rw, 0.01, 1000);
  world.robot.sonar_height_m = number(robot, "sonar_height_m", 0.25, rw, 0.01, 2);
  world.robot.camera_height_m = number(robot, "camera_height_m", 0.35, rw, 0.01, 2);
  check_spot(world, world.solid_segments(), start, "", world.robot.radius_m, rw, "start");
  for (const auto* group : {&world.map.furniture, &world.clutter}) {
    for (const auto& f : *group) {
      if (f.box.contains(start)) rw.fail("'start' " + fmt(start) + " is inside " + f.name);
    }
  }
  for (const Drop& d : world.drops) {
    if (d.box.contains(start)) rw.fail("'start' " + fmt(start) + " is on the step down " + d.name);
  }
  return world;
}

std::filesystem::path default_world_file() {
  return std::filesystem::path(MARVIN_SOURCE_DIR) / "examples" / "worlds" / "home.json";
}

}  // namespace marvin::sim
