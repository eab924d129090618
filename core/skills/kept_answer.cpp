#include "skills/kept_answer.h"

#include <string_view>
#include <tuple>
#include <type_traits>

#include "skills/host_api.h"

namespace marvin::skills {

void KeptAnswer::count_call() {
  std::lock_guard lock(mutex_);
  ++calls_;
}

std::optional<std::string> KeptAnswer::find(const std::string& call) {
  std::lock_guard lock(mutex_);
  if (!text_ || kept_at_ != calls_ || call_ != call) return std::nullopt;
  std::optional<std::string> text = std::move(text_);
  text_.reset();
  return text;
}

void KeptAnswer::keep(std::string call, std::string text) {
  std::lock_guard lock(mutex_);
  call_ = std::move(call);
  text_ = std::move(text);
  kept_at_ = calls_;
}

void KeptAnswer::clear() {
  std::lock_guard lock(mutex_);
  text_.reset();
}

namespace {

// The host's own functions behind the wrappers (filled once, with the table).
marvin_robot_api& own_functions() {
  static marvin_robot_api api{};
  return api;
}

// The buffer an acting call on this thread writes its answer into, and the full answer
// when it did not fit (set by note_truncated, from write_text).
struct AnswerWatch {
  const marvin_text_out* out = nullptr;
  std::optional<std::string> full;
};
thread_local AnswerWatch* answer_watch = nullptr;

// The arguments of a call, as part of what tells one call from another.
std::string call_part(const char* text) { return text ? std::string(text) : std::string("\x01"); }
std::string call_part(const marvin_text_out*) { return {}; }
template <class T, class = std::enable_if_t<std::is_arithmetic_v<T>>>
std::string call_part(T value) {
  return std::to_string(value);
}

template <class Slot, Slot slot>
struct Wrapper;

template <class... Args, marvin_status (*marvin_robot_api::*slot)(marvin_host*, Args...)>
struct Wrapper<marvin_status (*marvin_robot_api::*)(marvin_host*, Args...), slot> {
  static inline const char* name = "";

  static marvin_status acting(marvin_host* host, Args... args) {
    marvin_text_out* out = std::get<sizeof...(Args) - 1>(std::forward_as_tuple(args...));
    static_assert(
        std::is_same_v<std::remove_cv_t<std::remove_reference_t<decltype(out)>>, marvin_text_out*>);
    if (!host || !out) return (own_functions().*slot)(host, args...);
    KeptAnswer& kept = SkillContext::from(host).kept_answer();
    std::string call = name;
    ((call += '\x1f' + call_part(args)), ...);
    if (std::optional<std::string> answer = kept.find(call)) {
      // The retry of a call whose answer did not fit: the answer, without acting again.
      SkillContext::from(host).last_error.clear();
      const marvin_status status = write_text(out, *answer);
      if (status == MARVIN_ERR_TRUNCATED) {
        kept.keep(std::move(call), std::move(*answer));
        SkillContext::from(host).last_error = "the answer did not fit the buffer";
      }
      return status;
    }
    kept.count_call();
    AnswerWatch watch{out, std::nullopt};
    AnswerWatch* outer = answer_watch;
    answer_watch = &watch;
    const marvin_status status = (own_functions().*slot)(host, args...);
    answer_watch = outer;
    if (status == MARVIN_ERR_TRUNCATED && watch.full)
      kept.keep(std::move(call), std::move(*watch.full));
    return status;
  }
};

template <auto slot>
void wrap_acting(marvin_robot_api& api, const char* name) {
  using W = Wrapper<decltype(slot), slot>;
  own_functions().*slot = api.*slot;
  W::name = name;
  api.*slot = &W::acting;
}

}  // namespace

void keep_answers_of_acting_calls(marvin_robot_api& api) {
  // Calls that act (ask the user, add, capture, enroll, turn, guard, consume a phone event)
  // and write text.
  wrap_acting<&marvin_robot_api::ask>(api, "ask");
  wrap_acting<&marvin_robot_api::schedule_add>(api, "schedule_add");
  wrap_acting<&marvin_robot_api::contacts_add>(api, "contacts_add");
  wrap_acting<&marvin_robot_api::vision_capture_photo>(api, "vision_capture_photo");
  wrap_acting<&marvin_robot_api::vision_enroll_face>(api, "vision_enroll_face");
  wrap_acting<&marvin_robot_api::look_around>(api, "look_around");
  wrap_acting<&marvin_robot_api::guard>(api, "guard");
  wrap_acting<&marvin_robot_api::phone_wait_event>(api, "phone_wait_event");
}

void note_truncated(const marvin_text_out* out, std::string_view text) {
  if (answer_watch && answer_watch->out == out) answer_watch->full = std::string(text);
}

}  // namespace marvin::skills
