// The answer of an acting Robot API call (ask, look_around, schedule_add, phone_wait_event,
// ...) that did not fit the skill's buffer, kept for the skill's retry.
//
// The text contract (marvin/abi.h) lets a caller retry with a larger buffer after
// MARVIN_ERR_TRUNCATED. For a call that acts, a retry would act again: turn a second circle,
// add a second reminder, consume a second phone event. So the host keeps the answer that
// did not fit, and gives it to the skill's very next Robot API call when that call is the
// same function with the same arguments, without acting again. Any other call in between
// (last_error and is_cancelled excepted) drops it; so does a new request.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "marvin/robot.h"

namespace marvin::skills {

class KeptAnswer {
 public:
  // One Robot API call of the skill began (guarded calls and the acting wrappers).
  void count_call();
  // The answer kept for `call` (the function and its arguments) if the skill's previous
  // call was that very call and its answer did not fit.
  std::optional<std::string> find(const std::string& call);
  // `text`, the full answer of `call`, did not fit: keep it for the next call.
  void keep(std::string call, std::string text);
  // Drops what is kept (a new request begins).
  void clear();

 private:
  std::mutex mutex_;
  std::uint64_t calls_ = 0;
  std::uint64_t kept_at_ = 0;  // calls_ when the answer was kept
  std::string call_;
  std::optional<std::string> text_;
};

// Wraps the acting functions of `api` that write text so that their answers are kept when
// they do not fit (see above); and the finding functions so they count as calls. `api`
// holds the host's own functions; the wrappers call those.
void keep_answers_of_acting_calls(marvin_robot_api& api);

// Called by write_text for every answer that did not fit: kept when an acting call is
// writing into `out` on this thread.
void note_truncated(const marvin_text_out* out, std::string_view text);

}  // namespace marvin::skills
