// Robot API 1.3, finding and guarding (issue 22): look_around, sightings_find,
// rooms_to_search, place_find, turn, guard, events_list. The sightings every
// look records.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/log.h"
#include "skills/host_call.h"

namespace marvin::skills {
namespace {

using host_call::fail;
using host_call::guarded;
using host_call::need;
using host_call::need_service;
using nlohmann::json;

constexpr double kFindPi = 3.14159265358979323846;
// The head camera (sim/README.md; the real one is close): 60 degrees across 640
// pixels.
constexpr double kFieldOfViewDeg = 60;
// Sizes for a distance from a box's height: a face (chin to brow) and a small
// thing.
constexpr double kFaceHeightM = 0.18, kThingHeightM = 0.25;

// Typical heights (metres) of the COCO things a home robot is asked to find, for their
// distance from their box's height. One size for all put a bicycle (0.9 m) seen 3.5 m away
// through a door at 1 m, in the room the robot looked from: the wrong room. Things not
// listed (and objects taught by showing) keep kThingHeightM.
double thing_height_m(const std::string& coco_class) {
  static const std::pair<const char*, double> kHeights[] = {
      {"bicycle", 0.9},      {"motorcycle", 1.1},  {"dog", 0.5},         {"cat", 0.3},
      {"chair", 0.9},        {"couch", 0.8},       {"bed", 0.6},         {"tv", 0.55},
      {"suitcase", 0.6},     {"backpack", 0.45},   {"handbag", 0.3},     {"umbrella", 0.9},
      {"potted plant", 0.5}, {"teddy bear", 0.3},  {"laptop", 0.25},     {"bottle", 0.25},
      {"cup", 0.1},          {"wine glass", 0.18}, {"cell phone", 0.14}, {"remote", 0.18},
      {"book", 0.22},        {"clock", 0.3},       {"vase", 0.3}};
  for (const auto& [name, height] : kHeights) {
    if (coco_class == name) return height;
  }
  return kThingHeightM;
}

navigation::WaitFn finding_wait(SkillContext& c, navigation::GoingPlaces& going) {
  const double scale = going.time_scale() > 0 ? going.time_scale() : 1.0;
  return [&c, scale](std::chrono::milliseconds robot_ms) {
    auto wall =
        static_cast<std::uint32_t>(std::max(1.0, static_cast<double>(robot_ms.count()) / scale));
    return c.wait_cancelled_for(wall);
  };
}

marvin_status api_look_around(marvin_host* host, uint32_t stops, marvin_text_out* out) {
  return guarded(host, [&](SkillContext& c) {
    if (!out) return fail(c, MARVIN_ERR_INVALID, "the output buffer is NULL");
    if (stops == 0) stops = 8;
    if (stops < 4 || stops > 12) {
      return fail(c, MARVIN_ERR_INVALID,
                  "stops is " + std::to_string(stops) + ", expected 4 to 12 (or 0)");
    }
    MARVIN_TRY(need(c, {"camera", "motion"}));
    MARVIN_TRY(need_service(c, c.services().eyes, "camera"));
    MARVIN_TRY(need_service(c, c.services().going_places, "map to turn and look with"));
    navigation::GoingPlaces& going = *c.services().going_places;
    json seen = json::array();
    const double step = 360.0 / stops;
    for (std::uint32_t i = 0; i < stops; ++i) {
      if (c.cancelled()) return fail(c, MARVIN_ERR_CANCELLED, "the request was cancelled");
      for (json& s : record_sightings(c, c.services().eyes->look_json(), step * i)) {
        seen.push_back(std::move(s));
      }
      if (i + 1 < stops && !going.turn(step, finding_wait(c, going))) {
        going.stop();
        return fail(c, MARVIN_ERR_CANCELLED, "the motion was stopped");
      }
    }
    // Back to where it looked first, so a skill's next go_to starts as it
    // expects.
    going.turn(step, finding_wait(c, going));
    return write_text(out, json{{"stops", stops}, {"seen", seen}}.dump());
  });
}

marvin_status api_sightings_find(marvin_host* host, const char* what, int64_t since,
                                 marvin_text_out* out) {
  return guarded(host, [&](SkillContext& c) {
    if (!what || !out) return fail(c, MARVIN_ERR_INVALID, "what or the output is NULL");
    MARVIN_TRY(need(c, "camera"));
    MARVIN_TRY(need_service(c, c.services().sightings, "sightings log"));
    json rows = json::array();
    for (const data::Sighting& s : c.services().sightings->find(what, since)) {
      rows.push_back({{"what", s.what},
                      {"kind", s.kind},
                      {"room", s.room},
                      {"near", s.near},
                      {"seen_unix_ms", s.seen_utc_ms}});
    }
    return write_text(out, rows.dump());
  });
}

marvin_status api_rooms_to_search(marvin_host* host, marvin_text_out* out) {
  return guarded(host, [&](SkillContext& c) {
    if (!out) return fail(c, MARVIN_ERR_INVALID, "the output buffer is NULL");
    MARVIN_TRY(need(c, "sensors"));
    MARVIN_TRY(need_service(c, c.services().going_places, "map"));
    return write_text(out, json(c.services().going_places->rooms_to_search()).dump());
  });
}

marvin_status api_place_find(marvin_host* host, const char* name, marvin_text_out* out) {
  return guarded(host, [&](SkillContext& c) {
    if (!name || !out) return fail(c, MARVIN_ERR_INVALID, "name or the output is NULL");
    MARVIN_TRY(need(c, "sensors"));
    MARVIN_TRY(need_service(c, c.services().going_places, "map"));
    auto place = c.services().going_places->find_place(name);
    if (!place) {
      return fail(c, MARVIN_ERR_NOT_FOUND,
                  std::string("the map has no room, place or person called '") + name + "'");
    }
    json found{{"name", place->name}, {"kind", place->kind}, {"room", place->room}};
    if (auto metres = c.services().going_places->path_length_to(name)) {
      found["distance_m"] = std::round(*metres * 10) / 10;  // a decimetre is plenty to say
    }
    return write_text(out, found.dump());
  });
}

marvin_status api_turn(marvin_host* host, int32_t degrees) {
  return guarded(host, [&](SkillContext& c) {
    if (degrees < -360 || degrees > 360) {
      return fail(c, MARVIN_ERR_INVALID,
                  "degrees is " + std::to_string(degrees) + ", expected -360 to 360");
    }
    MARVIN_TRY(need(c, "motion"));
    MARVIN_TRY(need_service(c, c.services().going_places, "map to turn with"));
    navigation::GoingPlaces& going = *c.services().going_places;
    if (c.cancelled() || !going.turn(degrees, finding_wait(c, going))) {
      going.stop();
      return fail(c, MARVIN_ERR_CANCELLED, "the motion was stopped");
    }
    return MARVIN_OK;
  });
}

json guard_json(const GuardState& s) {
  return {{"on", s.on}, {"since_unix_ms", s.since_ms}, {"alerts", s.alerts}, {"by", s.by}};
}

marvin_status api_guard(marvin_host* host, int32_t mode, marvin_text_out* out) {
  return guarded(host, [&](SkillContext& c) {
    if (mode < -1 || mode > 1) {
      return fail(c, MARVIN_ERR_INVALID,
                  "mode is " + std::to_string(mode) + ", expected 1 (on), 0 (off) or -1");
    }
    MARVIN_TRY(need(c, "camera"));
    MARVIN_TRY(need_service(c, c.services().guard, "guard mode (no camera)"));
    Guard& guard = *c.services().guard;
    GuardState state;
    if (mode == 1) {
      state = guard.on();
    } else if (mode == 0) {
      // Only someone Marvin knows may call the guard off: a known face in view
      // now.
      std::string known;
      if (c.services().eyes) {
        for (const json& f :
             json::parse(c.services().eyes->look_json()).value("faces", json::array())) {
          if (!f.value("name", "").empty()) known = f.value("name", "");
        }
      }
      if (known.empty()) {
        return fail(c, MARVIN_ERR_PERMISSION,
                    "I can only stop guarding for someone I know, and I see no "
                    "face I know");
      }
      state = guard.off(known);
    } else {
      state = guard.state();
    }
    if (!out) return MARVIN_OK;
    return write_text(out, guard_json(state).dump());
  });
}

marvin_status api_events_list(marvin_host* host, const char* kind, int64_t since,
                              marvin_text_out* out) {
  return guarded(host, [&](SkillContext& c) {
    if (!kind || !out) return fail(c, MARVIN_ERR_INVALID, "kind or the output is NULL");
    MARVIN_TRY(need(c, "events"));
    MARVIN_TRY(need_service(c, c.services().events, "event log"));
    json rows = json::array();
    for (const auto& e : c.services().events(kind, since)) {
      rows.push_back({{"kind", e.kind}, {"message", e.message}, {"time_unix_ms", e.time_ms}});
    }
    return write_text(out, rows.dump());
  });
}

}  // namespace

json record_sightings(SkillContext& c, const std::string& seen_json, double bearing_offset_deg) {
  json out = json::array();
  try {
    const json seen = json::parse(seen_json);
    const double width = seen.value("width", 640.0);
    const double focal = width / 2 / std::tan(kFieldOfViewDeg / 2 * kFindPi / 180);
    auto add = [&](const json& item, const std::string& kind, const std::string& name,
                   double real_height) {
      const json box = item.value("box", json::array({0, 0, 0, 0}));
      const double cx = box[0].get<double>() + box[2].get<double>() / 2;
      const double h = std::max(1.0, box[3].get<double>());
      const double bearing = -std::atan((cx - width / 2) / focal) * 180 / kFindPi;
      const double distance = focal * real_height / h;
      json entry{{"kind", kind},
                 {"name", name},
                 {"bearing_deg", std::round(bearing + bearing_offset_deg)},
                 {"distance_m", std::round(distance * 10) / 10},
                 {"room", ""},
                 {"near", ""}};
      if (navigation::GoingPlaces* going = c.services().going_places) {
        if (auto spot = going->locate(bearing, distance)) {
          entry["room"] = spot->room;
          entry["near"] = spot->near;
        }
      }
      if (!name.empty() && c.services().sightings) {
        c.services().sightings->record({name, kind, entry["room"], entry["near"], 0});
      }
      out.push_back(std::move(entry));
    };
    for (const json& f : seen.value("faces", json::array())) {
      add(f, "person", f.value("name", ""), kFaceHeightM);
    }
    for (const json& o : seen.value("objects", json::array())) {
      add(o, "object", o.value("label", ""), thing_height_m(o.value("class", "")));
    }
  } catch (const std::exception& e) {
    log(LogLevel::kWarning, "sightings", std::string("not recorded: ") + e.what());
  }
  return out;
}

void add_finding_api(marvin_robot_api& a) {
  a.look_around = api_look_around;
  a.sightings_find = api_sightings_find;
  a.rooms_to_search = api_rooms_to_search;
  a.place_find = api_place_find;
  a.turn = api_turn;
  a.guard = api_guard;
  a.events_list = api_events_list;
}

}  // namespace marvin::skills
