// One slot's words -> its SlotValue, per slot type (see the table in interpreter.h).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "interpret/interpreter.h"

namespace marvin::interpret {

// Most words a text slot takes in an utterance (a dialogue answer may be longer).
inline constexpr std::size_t kTextSlotMaxWords = 8;

// A slot spec prepared once: list values normalised.
struct PreparedSlot {
  SlotSpec spec;
  std::vector<std::vector<std::string>> list_words;  // kList: normalised values[i]
  std::size_t max_words = 1;
  bool entity = false;  // kText naming a person or thing (slot_plausibility.h)
  bool device = false;  // kText naming a made thing: a `device` slot (slot_plausibility.h)
};

PreparedSlot prepare_slot(const SlotSpec& spec);

// Contact names normalised once per match() call (first use only).
class ContactBook {
 public:
  explicit ContactBook(const std::vector<std::string>& names) : names_(names) {}
  // The contact spelled as in Context::contact_names whose full name, or unique first name,
  // is `words` ("my daughter", a relation the host lists as a name, only in full).
  std::optional<std::string> find(std::span<const std::string> words) const;

 private:
  void prepare() const;
  const std::vector<std::string>& names_;
  mutable bool prepared_ = false;
  mutable std::vector<std::vector<std::string>> normalised_;
};

// Most words a contact name may have in an utterance.
inline constexpr std::size_t kContactMaxWords = 4;

// What the rest of the request says about its time: "wake me at 6" and "set an alarm for 7"
// mean the morning, though the time itself has no am/pm.
struct TimeCue {
  bool morning = false;
};

// The cue in a whole request's words: "wake", "waken", "alarm" or "alarms" anywhere.
TimeCue time_cue(std::span<const std::string> request);

// `words` (all of them) as a value of `slot`; nullopt if they are not one.
// `text_max_words` bounds kText; `cue` shifts an hour without am/pm (kDateTime). Throws
// std::runtime_error for an unknown time zone.
std::optional<SlotValue> read_slot_value(const PreparedSlot& slot,
                                         std::span<const std::string> words, const Context& context,
                                         const ContactBook& contacts, std::size_t text_max_words,
                                         TimeCue cue = {});

}  // namespace marvin::interpret
