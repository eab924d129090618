// Spoken durations -> seconds: "20 minutes", "an hour and a half", "half an hour",
// "2 hours and 30 minutes", "1 hour 20 minutes", "a quarter of an hour", "90 seconds",
// "2 and a half hours", "a couple of minutes", "1.5 hours".
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace marvin::interpret {

// Seconds per unit word ("second(s)", "sec(s)", "minute(s)", "min(s)", "hour(s)", "hr(s)",
// "day(s)", "week(s)"), or nullopt.
std::optional<std::int64_t> duration_unit_seconds(const std::string& word);

// The whole token span must be one duration (normalised tokens, numbers as digits).
// Returns whole seconds (> 0), or nullopt.
std::optional<std::int64_t> parse_duration(std::span<const std::string> words);

}  // namespace marvin::interpret
