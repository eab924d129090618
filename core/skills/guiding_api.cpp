// Robot API 1.4, guiding (issue 22): guide_to, go_to for leading a person who cannot see:
// slower, and telling the skill (on its own thread) what happens on the way.
#include <algorithm>
#include <cmath>

#include "skills/host_call.h"

namespace marvin::skills {
namespace {

using host_call::fail;
using host_call::guarded;
using host_call::need;
using host_call::need_service;
using host_call::need_text;
using host_call::trip_status;
using host_call::trip_wait;
using nlohmann::json;

// A skill's on_event must not start another trip (the navigator runs one at a time).
thread_local bool t_in_guide_event = false;

double rounded_cm(double m) { return std::round(m * 100.0) / 100.0; }

json event_json(const navigation::GoingPlaces::GuideEvent& e) {
  json j{{"event", e.event}, {"distance_left_m", rounded_cm(e.distance_left_m)}};
  if (e.event == "turn") {
    j["turn"] = e.turn;
    j["distance_m"] = rounded_cm(e.distance_m);
  } else if (e.event == "obstacle" || e.event == "step_down") {
    j["distance_m"] = rounded_cm(e.distance_m);
    j["kind"] = e.kind;
    j["stopped"] = e.stopped || e.event == "step_down";
  }
  return j;
}

marvin_status api_guide_to(marvin_host* host, const char* place, uint32_t speed_percent,
                           marvin_guide_event_fn on_event, void* user) {
  return guarded(host, [&](SkillContext& c) {
    MARVIN_TRY(need(c, "motion"));
    MARVIN_TRY(need_text(c, place, "place"));
    if (speed_percent > 100) {
      return fail(c, MARVIN_ERR_INVALID,
                  "speed_percent is " + std::to_string(speed_percent) + ", expected 0 to 100");
    }
    if (t_in_guide_event) {
      return fail(c, MARVIN_ERR_INVALID, "guide_to was called from its own on_event");
    }
    MARVIN_TRY(need_service(c, c.services().going_places, "map to go places with"));
    if (c.cancelled()) return fail(c, MARVIN_ERR_CANCELLED, "the request was cancelled");
    navigation::GoingPlaces& going = *c.services().going_places;
    const double factor = speed_percent == 0 ? 0.5 : std::max(10u, speed_percent) / 100.0;
    bool stopped_by_skill = false;
    navigation::GoingPlaces::GuideFn tell;
    if (on_event) {
      tell = [&](const navigation::GoingPlaces::GuideEvent& e) {
        const std::string text = event_json(e).dump();
        t_in_guide_event = true;
        const int stop = on_event(user, text.c_str());
        t_in_guide_event = false;
        if (stop != 0) stopped_by_skill = true;
        return stop == 0 && !c.cancelled();
      };
    }
    const navigation::GoResult r = going.guide_to(place, factor, tell, trip_wait(c, going));
    return trip_status(c, going, r,
                       stopped_by_skill ? "the skill stopped the trip" : "the motion was stopped");
  });
}

}  // namespace

void add_guiding_api(marvin_robot_api& a) { a.guide_to = api_guide_to; }

}  // namespace marvin::skills
