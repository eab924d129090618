#include "perception/wake_word_detector.h"

#include <stdexcept>

namespace marvin::perception {

std::size_t WakeWordDetector::process_features(std::span<const float>, std::int64_t,
                                               std::vector<WakeWordDetection>&) {
  throw std::logic_error("wake-word detector for \"" + keyword() +
                         "\" takes audio, not log-mel features");
}

}  // namespace marvin::perception
