#include "skills/manager.h"

#include <algorithm>
#include <exception>

#include "common/log.h"
#include "interpret/beyond_reach.h"

namespace marvin::skills {
namespace {

using nlohmann::json;

const char* status_name(marvin_status status) {
  switch (status) {
    case MARVIN_OK:
      return "ok";
    case MARVIN_ERR_PERMISSION:
      return "permission denied";
    case MARVIN_ERR_UNAVAILABLE:
      return "unavailable";
    case MARVIN_ERR_INVALID:
      return "invalid argument";
    case MARVIN_ERR_NOT_FOUND:
      return "not found";
    case MARVIN_ERR_CANCELLED:
      return "cancelled";
    case MARVIN_ERR_TRUNCATED:
      return "truncated";
    case MARVIN_ERR_INTERNAL:
      return "internal error";
  }
  return "unknown status";
}

// "Shall I call {contact}?" with each slot's value when it is text (a contact's name as
// spelled in the address book), otherwise the words the user said.
std::string fill_in(const std::string& text, const interpret::Match& match) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '{') {
      std::size_t close = text.find('}', i);
      if (close != std::string::npos) {
        auto slot = match.slots.find(text.substr(i + 1, close - i - 1));
        if (slot != match.slots.end()) {
          const json& value = slot->second.value;
          out += value.is_string() ? value.get<std::string>() : slot->second.text;
          i = close;
          continue;
        }
      }
    }
    out += text[i];
  }
  return out;
}

bool plain_words(const std::string& text) {
  return text.find_first_of("{}[]()|") == std::string::npos;
}

}  // namespace

Manager::Manager(Registry& registry, User& user, ManagerOptions options)
    : registry_(registry), user_(user), options_(options) {}

Manager::~Manager() {
  LoadedSkill* running = nullptr;
  {
    std::lock_guard lock(mutex_);
    cancelled_ = true;
    running = running_;
  }
  if (running) running->context->cancel();
  user_.interrupt();
  if (worker_.joinable()) worker_.join();
  if (watchdog_.joinable()) watchdog_.join();
}

void Manager::say(std::string_view text) {
  {
    std::lock_guard lock(mutex_);
    last_said_ = text;
  }
  user_.say(text);
}

std::optional<std::string> Manager::ask(std::string_view question) {
  {
    std::lock_guard lock(mutex_);
    if (cancelled_) return std::nullopt;
    last_said_ = question;
  }
  return user_.ask(question);
}

bool Manager::busy() const {
  std::lock_guard lock(mutex_);
  return busy_;
}

bool Manager::wait_idle(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return !busy_; });
}

bool Manager::idle() {
  join_finished();
  return !busy();
}

void Manager::join_finished() {
  if (busy()) return;
  if (worker_.joinable()) worker_.join();
  if (watchdog_.joinable()) watchdog_.join();
}

interpret::Context Manager::context() const {
  HostServices& s = registry_.services();
  interpret::Context c;
  c.now_utc_ms = s.now_ms ? s.now_ms() : system_now_ms();
  c.time_zone = s.time_zone;
  if (s.data) {
    try {
      for (const data::Contact& contact : s.data->list_contacts()) {
        c.contact_names.push_back(contact.name);
        for (const std::string& alias : contact.aliases) c.contact_names.push_back(alias);
        // "who is my doctor": the relation names the contact too; the skill's
        // contacts_find() resolves "my doctor" as the store does.
        if (!contact.relation.empty()) c.contact_names.push_back("my " + contact.relation);
      }
    } catch (const std::exception& e) {
      log(LogLevel::kWarning, "skills", std::string("contacts unavailable: ") + e.what());
    }
  }
  return c;
}

void Manager::light(int which) {
  if (devices::Body* body = registry_.services().body) {
    body->set_light(static_cast<devices::Light>(which));
  }
}

void Manager::stop() { end_task(false); }

void Manager::leave_task() { end_task(true); }

void Manager::end_task(bool leaving) {
  LoadedSkill* running = nullptr;
  std::string stopped;
  {
    std::lock_guard lock(mutex_);
    cancelled_ = true;
    running = running_;
    stopped = running_stopped_;
  }
  if (running) running->context->cancel();
  user_.interrupt();
  if (stop_hook_) {
    const std::string ended = stop_hook_(running ? running->manifest.id : std::string());
    if (!running && !ended.empty() && !leaving) return say(ended);
  }
  if (leaving) return say("OK, I'll leave that.");
  if (!running) return say("OK.");
  say(stopped.empty() ? "OK, I stopped." : stopped);
}

std::string Manager::no_match_sentence() {
  // One example per skill: its first intent's first example sentence (written to be said),
  // else its first template that is plain words.
  std::vector<std::string> examples;
  for (const auto& skill : registry_.skills()) {
    const std::vector<IntentDecl>& intents = skill->manifest.intents;
    if (!intents.empty() && !intents.front().examples.empty()) {
      examples.push_back(intents.front().examples.front());
      continue;
    }
    for (const IntentDecl& intent : intents) {
      auto plain = std::find_if(intent.templates.begin(), intent.templates.end(), plain_words);
      if (plain != intent.templates.end()) {
        examples.push_back(*plain);
        break;
      }
    }
  }
  if (!examples.empty()) {
    return "Sorry, I don't know how to help with that. You can ask me, for example: \"" +
           examples[refusals_++ % examples.size()] + "\".";
  }
  if (registry_.skills().empty()) {
    return "Sorry, I don't know how to help with that: no skills are installed.";
  }
  return "Sorry, I don't know how to help with that.";
}

void Manager::change_voice(interpret::VoiceChange change) {
  if (!voice_hook_) {
    say("I'm not speaking aloud now, so there is no voice to change.");
    return;
  }
  struct Way {
    int VoiceStyle::*field;
    int step;
    const char* done;   // said in the new voice
    const char* limit;  // said when it cannot go further
  };
  const Way way = [&]() -> Way {
    switch (change) {
      case interpret::VoiceChange::kSlower:
        return {&VoiceStyle::rate_steps, -1, "OK, I'll speak more slowly.",
                "This is as slowly as I can speak."};
      case interpret::VoiceChange::kFaster:
        return {&VoiceStyle::rate_steps, 1, "OK, I'll speak faster.",
                "This is as fast as I can speak."};
      case interpret::VoiceChange::kLouder:
        return {&VoiceStyle::volume_steps, 1, "OK, I'll speak louder.",
                "This is as loud as I can speak."};
      case interpret::VoiceChange::kQuieter:
        break;
    }
    return {&VoiceStyle::volume_steps, -1, "OK, I'll speak more quietly.",
            "This is as quietly as I can speak."};
  }();
  int& steps = voice_style_.*way.field;
  if (steps + way.step > kVoiceSteps || steps + way.step < -kVoiceSteps) {
    say(way.limit);
    return;
  }
  steps += way.step;
  voice_hook_(voice_style_);
  say(way.done);
}

void Manager::handle(std::string_view utterance) {
  join_finished();
  const interpret::Interpreter& interpreter = registry_.interpreter();
  switch (interpreter.builtin(utterance)) {
    case interpret::Builtin::kStop:
      stop();
      return;
    case interpret::Builtin::kRepeat: {
      std::string last;
      {
        std::lock_guard lock(mutex_);
        last = last_said_;
      }
      say(last.empty() ? "I haven't said anything yet." : last);
      return;
    }
    default:
      break;
  }
  if (std::optional<interpret::VoiceChange> change = interpret::voice_change(utterance)) {
    change_voice(*change);
    return;
  }
  std::string busy_with;
  {
    std::lock_guard lock(mutex_);
    if (busy_) {
      busy_with = running_ ? running_->manifest.name : "something";
    } else {
      cancelled_ = false;  // a new conversation starts
    }
  }
  if (!busy_with.empty()) {
    say("I'm still busy with " + busy_with + ". Say stop to interrupt.");
    return;
  }
  interpret::Builtin b = interpreter.builtin(utterance);
  if (b == interpret::Builtin::kYes || b == interpret::Builtin::kNo) {
    say("I wasn't asking anything. What can I do for you?");
    return;
  }

  interpret::Understanding understood = interpreter.understand(utterance, context());
  std::optional<interpret::Match> match;
  if (understood.outcome == interpret::Understanding::Outcome::kMatch) {
    match = std::move(understood.match);
  } else if (understood.outcome == interpret::Understanding::Outcome::kAsk) {
    // A wrong action is worse than a question.
    match = clarify(understood.choices);
    if (!match) return handle_next_request();
  }
  if (!match) {
    // At most the first 200 bytes: a 1 MB line must not flood the log.
    log(LogLevel::kInfo, "skills",
        "no match for \"" + std::string(utterance.substr(0, 200)) + "\"" +
            (utterance.size() > 200 ? " (" + std::to_string(utterance.size()) + " bytes)" : "") +
            " (" + understood.reason + ")");
    if (understood.negated) return say("OK, I won't.");
    std::optional<std::string> why = interpret::beyond_reach(utterance);
    say(why ? *why : no_match_sentence());
    return;
  }
  LoadedSkill* skill = registry_.find(match->skill_id);
  const IntentDecl* intent = skill ? skill->manifest.intent(match->intent) : nullptr;
  if (!intent) {
    log(LogLevel::kError, "skills",
        "the interpreter matched unknown " + match->skill_id + "/" + match->intent);
    say(no_match_sentence());
    return;
  }
  if (!fill_slots(*intent, *match, utterance)) return handle_next_request();
  if (intent->confirm && !confirm(*intent, *match)) return handle_next_request();
  run(*skill, *intent, *match, std::string(utterance));
}

bool Manager::fill_slots(const IntentDecl& intent, interpret::Match& match,
                         std::string_view utterance) {
  const interpret::Interpreter& interpreter = registry_.interpreter();
  for (const SlotDecl& slot : intent.slots) {
    if (!slot.required || match.slots.count(slot.name)) continue;
    interpret::SlotSpec spec = slot_spec(slot);
    bool filled = false;
    for (int attempt = 0; attempt < 2 && !filled; ++attempt) {
      std::optional<std::string> answer =
          ask(attempt == 0 ? slot.question : "Sorry, I didn't get that. " + slot.question);
      if (!answer) return false;  // stopped, or no answer will come
      if (interpreter.builtin(*answer) == interpret::Builtin::kStop) {
        stop();
        return false;
      }
      if (auto value = interpreter.parse_slot(spec, *answer, context(), utterance)) {
        match.slots[slot.name] = *value;
        filled = true;
      } else if (takes_as_request(*answer)) {
        return false;
      }
    }
    if (!filled) {
      say("Sorry, I still didn't understand. Let's leave it for now.");
      return false;
    }
  }
  return true;
}

std::string Manager::describe(const interpret::Match& match) const {
  LoadedSkill* skill = registry_.find(match.skill_id);
  const IntentDecl* intent = skill ? skill->manifest.intent(match.intent) : nullptr;
  if (intent && !intent->description.empty()) return intent->description;
  std::string name = match.intent;
  std::replace(name.begin(), name.end(), '_', ' ');
  return skill ? skill->manifest.name + " (" + name + ")" : name;
}

std::optional<interpret::Match> Manager::clarify(const std::vector<interpret::Match>& choices) {
  if (choices.size() < 2) return std::nullopt;
  const interpret::Interpreter& interpreter = registry_.interpreter();
  std::string first = describe(choices[0]);
  std::string second = describe(choices[1]);
  if (first == second) {  // two skills with the same intent ("a hello"): name the skills too
    auto skill_name = [&](const interpret::Match& m) {
      const LoadedSkill* skill = registry_.find(m.skill_id);
      return skill ? skill->manifest.name : m.skill_id;
    };
    first += " (" + skill_name(choices[0]) + ")";
    second += " (" + skill_name(choices[1]) + ")";
  }
  std::optional<std::string> answer = ask("Did you want " + first + " or " + second + "?");
  if (!answer) return std::nullopt;
  switch (interpreter.builtin(*answer)) {
    case interpret::Builtin::kStop:
      stop();
      return std::nullopt;
    case interpret::Builtin::kNo:
      say("OK.");
      return std::nullopt;
    default:
      break;
  }
  // "the first", "a reminder", "my schedule", or the request said again more clearly.
  std::string text;
  for (char c : *answer) text.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  auto mentions = [&](const std::string& description) {
    std::string lower;
    for (char c : description) lower.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    std::size_t at = 0;
    while (at < lower.size()) {
      std::size_t end = lower.find(' ', at);
      if (end == std::string::npos) end = lower.size();
      std::string word = lower.substr(at, end - at);
      if (word.size() > 3 && text.find(word) != std::string::npos) return true;
      at = end + 1;
    }
    return false;
  };
  const bool says_first = text.find("first") != std::string::npos || mentions(first);
  const bool says_second = text.find("second") != std::string::npos ||
                           text.find("other") != std::string::npos || mentions(second);
  if (says_first && !says_second) return choices[0];
  if (says_second && !says_first) return choices[1];
  interpret::Understanding again = interpreter.understand(*answer, context());
  if (again.outcome == interpret::Understanding::Outcome::kMatch) {
    for (const interpret::Match& choice : choices) {
      if (choice.skill_id == again.match->skill_id && choice.intent == again.match->intent) {
        return again.match;
      }
    }
  }
  if (takes_as_request(*answer)) return std::nullopt;
  say("Sorry, I didn't get that. Please ask me again.");
  return std::nullopt;
}

bool Manager::takes_as_request(const std::string& answer) {
  const interpret::Understanding u = registry_.interpreter().understand(answer, context());
  if (u.outcome != interpret::Understanding::Outcome::kMatch || u.match->confidence < 1.0F) {
    return false;
  }
  say("OK, I'll leave that.");
  next_request_ = answer;
  return true;
}

void Manager::handle_next_request() {
  if (!next_request_) return;
  const std::string next = std::move(*next_request_);
  next_request_.reset();
  handle(next);
}

Manager::Standing Manager::standing(std::string_view utterance) const {
  const interpret::Interpreter& interpreter = registry_.interpreter();
  if (interpreter.builtin(utterance) != interpret::Builtin::kNone) return Standing::kNone;
  const interpret::Understanding u = interpreter.understand(utterance, context());
  if (u.outcome != interpret::Understanding::Outcome::kMatch) return Standing::kNone;
  if (u.match->confidence < 1.0F) return Standing::kLikely;
  const LoadedSkill* skill = registry_.find(u.match->skill_id);
  const IntentDecl* intent = skill ? skill->manifest.intent(u.match->intent) : nullptr;
  std::lock_guard lock(mutex_);
  // "Help! Help!": a second call for help does not stop the first.
  const bool urgent = intent && intent->urgent && !(busy_ && running_urgent_);
  return urgent ? Standing::kUrgent : Standing::kRequest;
}

bool Manager::confirm(const IntentDecl& intent, const interpret::Match& match) {
  const interpret::Interpreter& interpreter = registry_.interpreter();
  std::string question = fill_in(intent.confirm_question, match);
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::optional<std::string> answer =
        ask(attempt == 0 ? question : "Please answer yes or no. " + question);
    if (!answer) return false;
    switch (interpreter.builtin(*answer)) {
      case interpret::Builtin::kYes:
        return true;
      case interpret::Builtin::kNo:
        say("OK, I won't.");
        return false;
      case interpret::Builtin::kStop:
        stop();
        return false;
      default:
        if (takes_as_request(*answer)) return false;
        break;
    }
  }
  say("I'll take that as a no.");
  return false;
}

void Manager::run(LoadedSkill& skill, const IntentDecl& intent, const interpret::Match& match,
                  std::string utterance) {
  json slots = json::object();
  for (const auto& [name, value] : match.slots) slots[name] = value.value;
  std::string slots_json = slots.dump();
  // Cleared here, on the loop thread, so a "stop" arriving before the worker starts counts.
  skill.context->begin_request();
  {
    std::lock_guard lock(mutex_);
    running_ = &skill;
    running_stopped_ = intent.stopped;
    running_urgent_ = intent.urgent;
    timed_out_ = false;
  }
  if (intent.execution == Execution::kShort || options_.run_long_inline) {
    execute(skill, intent.name, slots_json, utterance, false);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    busy_ = true;
  }
  auto limit = std::chrono::milliseconds{intent.time_limit_ms};
  worker_ = std::thread([this, &skill, name = intent.name, slots_json, utterance] {
    execute(skill, name, slots_json, utterance, true);
  });
  watchdog_ = std::thread([this, &skill, limit] {
    std::unique_lock lock(mutex_);
    if (changed_.wait_for(lock, limit, [&] { return !busy_; })) return;
    timed_out_ = true;
    lock.unlock();
    log(LogLevel::kWarning, "skills", "skill '" + skill.manifest.id + "' ran out of time");
    skill.context->cancel();
    user_.interrupt();
  });
}

void Manager::execute(LoadedSkill& skill, const std::string& intent, const std::string& slots_json,
                      const std::string& utterance, bool timed) {
  light(static_cast<int>(devices::Light::kExecuting));
  marvin_request request{sizeof(marvin_request), intent.c_str(), slots_json.c_str(),
                         utterance.c_str()};
  std::string error;
  marvin_status status = MARVIN_ERR_INTERNAL;
  try {
    status = skill.instance->handle(request, &error);
  } catch (const std::exception& e) {
    error = std::string("exception escaped the skill runtime: ") + e.what();
  } catch (...) {
    error = "unknown exception escaped the skill runtime";
  }
  report(skill, intent, status, error);
  light(static_cast<int>(devices::Light::kAwaiting));
  {
    std::lock_guard lock(mutex_);
    running_ = nullptr;
    if (timed) busy_ = false;
  }
  changed_.notify_all();
  if (timed) user_.task_finished();
}

void Manager::report(LoadedSkill& skill, const std::string& intent, marvin_status status,
                     const std::string& error) {
  if (status == MARVIN_OK) return;
  bool timed_out = false;
  {
    std::lock_guard lock(mutex_);
    timed_out = timed_out_;
  }
  if (status == MARVIN_ERR_CANCELLED) {
    // "stop" has already been answered; a time limit has not.
    if (timed_out) say("Sorry, that took too long, so I stopped.");
    return;
  }
  std::string message = "skill '" + skill.manifest.id + "' intent '" + intent + "' failed (" +
                        status_name(status) + "): " + error;
  log(LogLevel::kError, "skills", message);
  if (data::PersonalData* data = registry_.services().data) {
    try {
      data->log_event("skill_error", skill.manifest.id, message);
    } catch (const std::exception& e) {
      log(LogLevel::kError, "skills", std::string("cannot record the event: ") + e.what());
    }
  }
  say("Sorry, something went wrong with " + skill.manifest.name + ".");
}

}  // namespace marvin::skills
