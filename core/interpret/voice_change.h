// "Speak slower", "louder please", "you're talking too fast", "I can't hear you": asking
// Marvin to change how it speaks. Like stop/yes/no/repeat these are the host's, not a
// skill's: they change the voice every skill speaks with.
#pragma once

#include <optional>
#include <string_view>

namespace marvin::interpret {

enum class VoiceChange { kSlower, kFaster, kLouder, kQuieter };

// The change asked for, or nullopt when `utterance` asks something else. Only whole short
// requests about Marvin's own voice count: "turn the radio down", "slow down" (said to a
// robot that moves) and "speak to Anna" are not.
std::optional<VoiceChange> voice_change(std::string_view utterance);

}  // namespace marvin::interpret
