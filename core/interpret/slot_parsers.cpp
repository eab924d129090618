#include "interpret/slot_parsers.h"

#include <algorithm>
#include <cmath>

#include "interpret/durations.h"
#include "interpret/normalizer.h"
#include "interpret/number_words.h"
#include "interpret/slot_plausibility.h"
#include "interpret/time_expression.h"
#include "interpret/time_resolution.h"
#include "interpret/wordnet.h"

namespace marvin::interpret {
namespace {

bool is_speaker(const std::string& word) {
  return word == "me" || word == "us" || word == "myself" || word == "ourselves";
}

std::string join(std::span<const std::string> words) {
  std::string out;
  for (const std::string& w : words) {
    if (!out.empty()) out.push_back(' ');
    out += w;
  }
  return out;
}

bool equal_words(std::span<const std::string> a, const std::vector<std::string>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end());
}

}  // namespace

PreparedSlot prepare_slot(const SlotSpec& spec) {
  PreparedSlot slot;
  slot.spec = spec;
  switch (spec.type) {
    case SlotType::kNumber:
      slot.max_words = 1;
      break;
    case SlotType::kDuration:
    case SlotType::kDateTime:
      slot.max_words = 12;
      break;
    case SlotType::kContact:
      slot.max_words = kContactMaxWords;
      break;
    case SlotType::kList:
      slot.max_words = 1;
      for (const std::string& value : spec.values) {
        slot.list_words.push_back(normalize(value));
        slot.max_words = std::max(slot.max_words, slot.list_words.back().size());
      }
      break;
    case SlotType::kText:
      slot.max_words = kTextSlotMaxWords;
      slot.entity = is_entity_slot(spec.name);
      slot.device = is_device_slot(spec.name);
      break;
  }
  return slot;
}

void ContactBook::prepare() const {
  if (prepared_) return;
  prepared_ = true;
  normalised_.reserve(names_.size());
  for (const std::string& name : names_) normalised_.push_back(normalize(name));
}

std::optional<std::string> ContactBook::find(std::span<const std::string> words) const {
  prepare();
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (!normalised_[i].empty() && equal_words(words, normalised_[i])) return names_[i];
  }
  // "Anna" for "Anna Schmidt", only when no other contact is called Anna. ("My" of a
  // relation, "my daughter", is no first name.)
  if (words.size() != 1 || words[0] == "my") return std::nullopt;
  std::optional<std::size_t> found;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (normalised_[i].size() > 1 && normalised_[i][0] == words[0]) {
      if (found) return std::nullopt;
      found = i;
    }
  }
  if (found) return names_[*found];
  return std::nullopt;
}

TimeCue time_cue(std::span<const std::string> request) {
  TimeCue cue;
  for (const std::string& w : request) {
    if (w == "wake" || w == "waken" || w == "alarm" || w == "alarms") cue.morning = true;
  }
  return cue;
}

std::optional<SlotValue> read_slot_value(const PreparedSlot& slot,
                                         std::span<const std::string> words, const Context& context,
                                         const ContactBook& contacts, std::size_t text_max_words,
                                         TimeCue cue) {
  if (words.empty()) return std::nullopt;
  switch (slot.spec.type) {
    case SlotType::kNumber: {
      if (words.size() != 1) return std::nullopt;
      auto value = parse_decimal(words[0]);
      if (!value) return std::nullopt;
      double whole = std::floor(*value);
      if (whole == *value) {
        return SlotValue{words[0], nlohmann::json(static_cast<std::int64_t>(whole))};
      }
      return SlotValue{words[0], nlohmann::json(*value)};
    }
    case SlotType::kDuration: {
      auto seconds = parse_duration(words);
      if (!seconds) return std::nullopt;
      return SlotValue{join(words), nlohmann::json(*seconds)};
    }
    case SlotType::kDateTime: {
      std::vector<TimePhrase> phrases = parse_time_phrases(words);
      if (phrases.empty()) return std::nullopt;
      // "at 9 am and 9 pm": the first time is the value, the others are listed in "also".
      nlohmann::json value;
      for (TimePhrase& phrase : phrases) {
        if (cue.morning && !phrase.evening) phrase.morning = true;
        auto resolved = resolve_time_phrase(phrase, context.now_utc_ms, context.time_zone);
        if (!resolved) return std::nullopt;
        if (value.is_null()) {
          value = std::move(*resolved);
        } else if ((*resolved)["at"] == value["at"]) {
          return std::nullopt;  // "at 8 pm and 8 pm": one time said twice is no pair
        } else {
          value["also"].push_back(std::move(*resolved));
        }
      }
      return SlotValue{join(words), std::move(value)};
    }
    case SlotType::kContact: {
      auto name = contacts.find(words);
      if (!name) return std::nullopt;
      return SlotValue{join(words), nlohmann::json(*name)};
    }
    case SlotType::kList:
      for (std::size_t i = 0; i < slot.list_words.size(); ++i) {
        if (equal_words(words, slot.list_words[i])) {
          return SlotValue{join(words), nlohmann::json(slot.spec.values[i])};
        }
      }
      return std::nullopt;
    case SlotType::kText: {
      if (words.size() > text_max_words) return std::nullopt;
      // "me"/"us" (first) and "you" (alone) name the speaker or Marvin, never the person or
      // thing a slot asks for: without this, "tell me a joke" would fill "tell {name}
      // {message}" with name "me a".
      if (!words.empty() && (is_speaker(words[0]) || (words.size() == 1 && words[0] == "you"))) {
        return std::nullopt;
      }
      // "the" or "of the" is no value; a person or thing must look like one.
      if (only_function_words(words)) return std::nullopt;
      // Nor is a time alone: "remind me at 6" must not make "at 6" the task.
      if (!parse_time_phrases(words).empty()) return std::nullopt;
      if (slot.entity && !contacts.find(words) && !plausible_entity(words, WordNet::installed())) {
        return std::nullopt;
      }
      if (slot.device && !contacts.find(words) && !plausible_device(words, WordNet::installed())) {
        return std::nullopt;
      }
      std::string text = join(words);
      return SlotValue{text, nlohmann::json(text)};
    }
  }
  return std::nullopt;
}

}  // namespace marvin::interpret
