// The people, devices and home pages' operations (API.md). People go through
// vision::FaceGallery, as `marvin people ...` does; devices through the host's smart home
// (skills::SmartHome: the same "set and confirm" a voice command or a skill uses); the home
// map is the navigator's floor plan, the robot's pose and the store's sightings.
#include <cmath>
#include <numbers>
#include <opencv2/imgcodecs.hpp>

#include "data/recurrence.h"
#include "data/sqlite_store.h"
#include "skills/smart_home.h"
#include "vision/face_gallery.h"
#include "vision/face_pipeline.h"
#include "web/api.h"

namespace marvin::web {

using nlohmann::json;

namespace {

// The person with id `id_text`, or 404 naming it.
data::Person person_by_id(data::SqliteStore& store, const std::string& id_text) {
  const std::int64_t id = parse_id(id_text, "person");
  for (const data::Person& p : store.list_people())
    if (p.id == id) return p;
  throw ApiError(404, "no person with id " + std::to_string(id) + " is enrolled");
}

json point_json(navigation::Vec2 p) { return json::array({p.x, p.y}); }

json floor_map_json(const navigation::FloorMap& map) {
  const navigation::Box b = map.bounds();
  json out = {{"bounds", {point_json(b.min), point_json(b.max)}},
              {"walls", json::array()},
              {"rooms", json::array()},
              {"doors", json::array()},
              {"furniture", json::array()},
              {"places", json::array()}};
  for (const navigation::Segment& w : map.walls)
    out["walls"].push_back({point_json(w.a), point_json(w.b)});
  for (const navigation::Room& r : map.rooms) {
    json outline = json::array();
    for (const navigation::Vec2& p : r.outline) outline.push_back(point_json(p));
    out["rooms"].push_back({{"name", r.name}, {"outline", outline}, {"spot", point_json(r.spot)}});
  }
  for (const navigation::Door& d : map.doors)
    out["doors"].push_back(
        {{"name", d.name}, {"a", point_json(d.a)}, {"b", point_json(d.b)}, {"open", d.open}});
  for (const navigation::Furniture& f : map.furniture)
    out["furniture"].push_back(
        {{"name", f.name}, {"min", point_json(f.box.min)}, {"max", point_json(f.box.max)}});
  for (const navigation::Place& p : map.places)
    out["places"].push_back({{"name", p.name}, {"at", point_json(p.at)}, {"room", p.room}});
  return out;
}

}  // namespace

Api::~Api() = default;

ApiResponse Api::enroll_person(const ApiRequest& r) {
  auto name = r.query.find("name");
  if (name == r.query.end() || name->second.empty())
    throw ApiError(400, "name: missing; send /api/people/enroll?name=NAME with a photo of them");
  if (r.body.empty()) throw ApiError(400, "photo: empty; send a JPEG or PNG photo of them alone");
  const cv::Mat bytes(1, static_cast<int>(r.body.size()), CV_8U, const_cast<char*>(r.body.data()));
  const cv::Mat image = cv::imdecode(bytes, cv::IMREAD_COLOR);
  if (image.empty()) throw ApiError(400, "photo: not a JPEG or PNG image");
  try {
    if (!faces_) faces_ = std::make_unique<vision::FacePipeline>();
  } catch (const std::exception& e) {
    throw ApiError(503, std::string("cannot learn faces here: ") + e.what());
  }
  std::vector<float> embedding;
  try {
    // The same rule as `marvin people enroll`: exactly one face on the photo.
    auto file = r.query.find("file");
    embedding = vision::lone_face_embedding(
        *faces_, image, file == r.query.end() ? "upload" : file->second, name->second);
  } catch (const std::invalid_argument& e) {
    throw ApiError(422, std::string(e.what()) + "; nothing was enrolled");
  }
  vision::FaceGallery gallery(store_);
  const std::int64_t id = gallery.enroll(name->second, {embedding}, "web");
  const std::string stored = gallery.find(name->second)->name;
  return {201, {{"id", id}, {"name", stored}, {"faces", store_.face_embeddings(id).size()}}};
}

ApiResponse Api::people(const ApiRequest& r, const std::string& id) {
  if (r.method == "POST" && id == "enroll") return enroll_person(r);
  vision::FaceGallery gallery(store_);
  if (r.method == "GET" && id.empty()) {
    json list = json::array();
    for (const vision::GalleryPerson& p : gallery.list()) {
      list.push_back(
          {{"id", p.person_id},
           {"name", p.name},
           {"faces", p.embeddings},
           {"enrolled_by", p.last_enrolled_by},
           {"enrolled", p.last_enrolled_utc_ms
                            ? json(data::format_local(p.last_enrolled_utc_ms, options_.time_zone))
                            : json(nullptr)}});
    }
    return {200, list};
  }
  if (r.method == "PUT" && !id.empty()) {
    const data::Person person = person_by_id(store_, id);
    const json doc = parse_body(r.body);
    auto name = doc.find("name");
    if (name == doc.end() || !name->is_string())
      throw ApiError(400, "field 'name': expected the person's new name as a string");
    try {
      gallery.rename(person.name, name->get<std::string>(), "web");
    } catch (const std::invalid_argument& e) {
      // "new name: ..." from the gallery; on the page the field is called name.
      std::string message = e.what();
      if (message.rfind("new name: ", 0) == 0) message = message.substr(10);
      throw ApiError(400, "field 'name': " + message);
    }
    return {200, {{"id", person.id}, {"name", name->get<std::string>()}}};
  }
  if (r.method == "DELETE" && !id.empty()) {
    const data::Person person = person_by_id(store_, id);
    gallery.forget(person.name, "web");
    return {200, {{"forgotten", person.id}, {"name", person.name}}};
  }
  throw ApiError(405, r.method + " " + r.path + ": not an operation on people (see API.md)");
}

ApiResponse Api::devices(const ApiRequest& r, const std::string& id) {
  skills::SmartHome* home = options_.smart_home;
  if (r.method == "GET" && id.empty()) {
    if (!home)
      return {200, {{"configured", false}, {"connected", false}, {"devices", json::array()}}};
    json out = home->devices();
    out["configured"] = true;
    return {200, out};
  }
  if (r.method == "POST" && !id.empty()) {
    if (!home)
      throw ApiError(503,
                     "no smart home here: Marvin runs without one (see `marvin devices` and "
                     "home.json)");
    const json doc = parse_body(r.body);
    json state = json::object();
    if (auto on = doc.find("on"); on != doc.end() && !on->is_null()) {
      if (!on->is_boolean()) throw ApiError(400, "field 'on': expected true or false");
      state["on"] = on->get<bool>();
    }
    if (auto b = doc.find("brightness"); b != doc.end() && !b->is_null()) {
      if (!b->is_number_integer() || b->get<std::int64_t>() < 0 || b->get<std::int64_t>() > 100)
        throw ApiError(400, "field 'brightness': expected a whole number 0..100 (percent)");
      state["brightness"] = b->get<int>();
    }
    if (auto t = doc.find("target_temperature"); t != doc.end() && !t->is_null()) {
      if (!t->is_number() || t->get<double>() <= -50.0 || t->get<double>() >= 100.0)
        throw ApiError(400, "field 'target_temperature': expected degrees Celsius (a number)");
      state["target_temperature"] = t->get<double>();
    }
    if (state.empty())
      throw ApiError(400, "field 'on': missing (or give 'brightness' or 'target_temperature')");
    const skills::SmartHome::Reply reply = home->set(id, state);
    switch (reply.result) {
      case skills::SmartHome::Result::kDone:
        return {200, reply.device};
      case skills::SmartHome::Result::kNotFound:
        throw ApiError(404, reply.sentence);
      case skills::SmartHome::Result::kInvalid:
        throw ApiError(400, reply.sentence);
      case skills::SmartHome::Result::kUnavailable:
        throw ApiError(503, reply.sentence);
    }
  }
  throw ApiError(405, r.method + " " + r.path + ": not an operation on devices (see API.md)");
}

ApiResponse Api::home() {
  json out = {{"map", nullptr}, {"robot", nullptr}, {"sightings", json::array()}};
  if (options_.floor_map) out["map"] = floor_map_json(*options_.floor_map);
  if (options_.robot_pose) {
    if (const std::optional<navigation::Pose> pose = options_.robot_pose()) {
      const navigation::Room* room =
          options_.floor_map ? options_.floor_map->room_at(pose->position()) : nullptr;
      out["robot"] = {{"at", point_json(pose->position())},
                      {"heading_deg", pose->heading * 180 / std::numbers::pi},
                      {"room", room ? json(room->name) : json(nullptr)}};
    }
  }
  for (const data::Sighting& s : store_.sightings("")) {
    if (out["sightings"].size() == 50) break;
    out["sightings"].push_back({{"what", s.what},
                                {"kind", s.kind},
                                {"room", s.room},
                                {"near", s.near},
                                {"seen", data::format_local(s.seen_utc_ms, options_.time_zone)}});
  }
  return {200, out};
}

}  // namespace marvin::web
