#include "web/live.h"

namespace marvin::web {

void LiveFeed::console_line(std::string_view line) {
  std::string kind;
  nlohmann::json data;
  {
    std::lock_guard lock(mutex_);
    if (line.size() >= 2 && line.front() == '[' && line.back() == ']') {
      const std::string inner(line.substr(1, line.size() - 2));
      if (inner.rfind("light: ", 0) == 0) {
        light_ = inner.substr(7);
      } else if (inner.rfind("web page:", 0) == 0 || inner.rfind("home:", 0) == 0 ||
                 inner.rfind("base:", 0) == 0) {
        return;  // the host's notices about itself, not something Marvin does
      } else {
        doing_ = inner;
      }
      kind = "status";
      data = {{"light", light_}, {"doing", doing_}};
    } else {
      std::string who = "note";
      std::string text(line);
      if (const auto colon = text.find(": "); colon != std::string::npos && colon <= 6) {
        const std::string speaker = text.substr(0, colon);
        if (speaker == "Marvin" || speaker == "You") {
          who = speaker;
          text = text.substr(colon + 2);
        }
      }
      if (who == "note") return;  // greetings and hints of the console are not turns
      data = {{"who", who}, {"text", text}};
      turns_.push_back(data);
      while (turns_.size() > kTurns) turns_.pop_front();
      kind = "turn";
    }
  }
  std::lock_guard listening(listener_mutex_);
  if (listener_) listener_(kind, data);
}

nlohmann::json LiveFeed::snapshot() const {
  std::lock_guard lock(mutex_);
  nlohmann::json turns = nlohmann::json::array();
  for (const auto& t : turns_) turns.push_back(t);
  return {{"light", light_}, {"doing", doing_}, {"turns", turns}};
}

void LiveFeed::set_listener(Listener listener) {
  std::lock_guard listening(listener_mutex_);
  listener_ = std::move(listener);
}

}  // namespace marvin::web
