// How every Robot API call the host implements runs (host_api.cpp,
// finding_api.cpp): one guard that turns exceptions into a status and an error
// sentence, so nothing escapes across the C ABI, and the checks each call
// starts with (permission, arguments, services). Internal to core/skills:
// included by the files that fill in `marvin_robot_api`, never by a skill.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <exception>
#include <initializer_list>
#include <string>

#include "skills/eyes.h"
#include "skills/host_api.h"

namespace marvin::skills::host_call {

// Runs one Robot API call for a context: records the error sentence on failure,
// and turns any exception into a status. A camera that failed underneath
// (EyesUnavailable, thrown from anywhere in the call) is
// MARVIN_ERR_UNAVAILABLE, not an internal error: a skill tells the user "my
// camera stopped working", it does not report a bug.
template <class F>
marvin_status guarded(marvin_host* host, F&& body) {
  if (!host) return MARVIN_ERR_INVALID;
  SkillContext& c = SkillContext::from(host);
  c.last_error.clear();
  c.kept_answer().count_call();  // a retry must follow its call at once (kept_answer.h)
  try {
    return body(c);
  } catch (const EyesUnavailable& e) {
    c.last_error = e.what();
    return MARVIN_ERR_UNAVAILABLE;
  } catch (const std::exception& e) {
    c.last_error = e.what();
    return MARVIN_ERR_INTERNAL;
  } catch (...) {
    c.last_error = "unknown error in the host";
    return MARVIN_ERR_INTERNAL;
  }
}

inline marvin_status fail(SkillContext& c, marvin_status status, std::string sentence) {
  c.last_error = std::move(sentence);
  return status;
}

inline marvin_status need(SkillContext& c, const char* permission) {
  if (c.has_permission(permission)) return MARVIN_OK;
  return fail(c, MARVIN_ERR_PERMISSION,
              std::string("permission '") + permission + "' is not granted to skill '" +
                  c.skill_id() + "'");
}

// Several permissions at once; the first one missing is named.
inline marvin_status need(SkillContext& c, std::initializer_list<const char*> permissions) {
  for (const char* p : permissions) {
    if (marvin_status s = need(c, p); s != MARVIN_OK) return s;
  }
  return MARVIN_OK;
}

inline marvin_status need_text(SkillContext& c, const char* text, const char* what) {
  if (text) return MARVIN_OK;
  return fail(c, MARVIN_ERR_INVALID, std::string(what) + " is NULL");
}

inline marvin_status need_out(SkillContext& c, marvin_text_out* out) {
  if (out) return MARVIN_OK;
  return fail(c, MARVIN_ERR_INVALID, "the output buffer is NULL");
}

// `service` is a pointer or anything testable as a bool (a std::function).
template <class Service>
marvin_status need_service(SkillContext& c, const Service& service, const char* what) {
  if (service) return MARVIN_OK;
  return fail(c, MARVIN_ERR_UNAVAILABLE, std::string("this robot has no ") + what);
}

// How a trip (go_to, guide_to) waits between the navigator's control steps: `robot_ms` of
// robot time as wall time (the simulation may run faster), woken at once by "stop" (the
// request's cancel()), so the navigator stops the wheels before returning. True: cancelled.
inline auto trip_wait(SkillContext& c, const navigation::GoingPlaces& going) {
  const double scale = going.time_scale() > 0 ? going.time_scale() : 1.0;
  return [&c, scale](std::chrono::milliseconds robot_ms) {
    auto wall = static_cast<std::uint32_t>(
        std::max(1.0, static_cast<double>(robot_ms.count()) / scale));
    return c.wait_cancelled_for(wall);
  };
}

// What a finished trip tells the skill: MARVIN_OK there; NOT_FOUND for a place the map does
// not know; CANCELLED (wheels stopped) with `cancelled_why`; UNAVAILABLE with the reason.
inline marvin_status trip_status(SkillContext& c, navigation::GoingPlaces& going,
                                 const navigation::GoResult& r, const char* cancelled_why) {
  switch (r.outcome) {
    case navigation::GoResult::Outcome::kArrived:
      return MARVIN_OK;
    case navigation::GoResult::Outcome::kUnknownPlace:
      return fail(c, MARVIN_ERR_NOT_FOUND, r.reason);
    case navigation::GoResult::Outcome::kCancelled:
      going.stop();
      return fail(c, MARVIN_ERR_CANCELLED, cancelled_why);
    case navigation::GoResult::Outcome::kGaveUp:
      break;
  }
  return fail(c, MARVIN_ERR_UNAVAILABLE, r.reason);
}

}  // namespace marvin::skills::host_call

// Returns the status of `expr` from the enclosing call unless it is MARVIN_OK.
#define MARVIN_TRY(expr)                                       \
  do {                                                         \
    if (marvin_status s_ = (expr); s_ != MARVIN_OK) return s_; \
  } while (0)
