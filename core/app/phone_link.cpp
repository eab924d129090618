#include "app/phone_link.h"

#include <algorithm>

#include "common/log.h"

namespace marvin::app {
namespace {

using nlohmann::json;
using telephony::CallEnd;
using telephony::CallState;
using telephony::PhoneEvent;

const char* state_name(CallState state) {
  switch (state) {
    case CallState::kIdle: return "idle";
    case CallState::kCalling: return "calling";
    case CallState::kRinging: return "ringing";
    case CallState::kInCall: return "in_call";
    case CallState::kIncoming: return "incoming";
  }
  return "idle";
}

const char* end_event(CallEnd end) {
  switch (end) {
    case CallEnd::kBusy: return "busy";
    case CallEnd::kNoAnswer: return "no_answer";
    case CallEnd::kFailed: return "failed";
    case CallEnd::kHungUp:
    case CallEnd::kRemoteHungUp: return "ended";
  }
  return "ended";
}

// "sip:0301555@127.0.0.1:5060" -> "0301555"; "sip:anna@example.org" stays as it is.
std::string shown(const std::string& uri) {
  if (uri.rfind("sip:", 0) != 0) return uri;
  const std::string user = uri.substr(4, uri.find('@') - 4);
  const bool digits = !user.empty() && std::all_of(user.begin(), user.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) || c == '+';
  });
  return digits ? user : uri;
}

constexpr char kAnswered[] = " answered the emergency call";
constexpr char kNobody[] = "Nobody answered the emergency call";

}  // namespace

PhoneLink::PhoneLink(telephony::PhoneSettings settings, std::filesystem::path config_dir,
                     PhoneLinkHooks hooks, std::chrono::milliseconds no_answer_timeout)
    : hooks_(std::move(hooks)) {
  phone_ = std::make_unique<telephony::Phone>(
      std::move(settings), std::move(config_dir),
      [this](const PhoneEvent& event) { on_event(event); }, no_answer_timeout);
}

PhoneLink::~PhoneLink() {
  std::shared_ptr<telephony::EmergencyCall> help;
  {
    std::lock_guard lock(mutex_);
    help = std::move(help_);
  }
  help.reset();  // stops trying before the phone goes
  // The last events are delivered while phone_ still points at the phone (on_event uses it;
  // unique_ptr::reset clears the pointer before the destructor runs).
  if (phone_) phone_->stop();
  phone_.reset();
}

void PhoneLink::start() { phone_->start(); }

std::string PhoneLink::uri_of(const std::string& number) const {
  std::string uri = phone_->uri_for(number);
  if (!uri.empty() && hooks_.route) uri = hooks_.route(uri);
  return uri;
}

std::string PhoneLink::name_for(const std::string& uri) {
  if (uri == uri_ && !name_.empty()) return name_;
  std::string name = hooks_.name_of ? hooks_.name_of(uri) : std::string();
  return name.empty() ? shown(uri) : name;
}

void PhoneLink::push(json event) {
  event["number"] = uri_;
  event["name"] = name_.empty() ? shown(uri_) : name_;
  events_.push_back(std::move(event));
  changed_.notify_all();
}

skills::Telephone::Reply PhoneLink::dial(const std::string& number, const std::string& name) {
  const std::string uri = uri_of(number);
  if (uri.empty()) {
    return {Result::kInvalid,
            "number: \"" + number + "\" is neither a phone number nor a sip: address"};
  }
  {
    std::lock_guard lock(mutex_);
    if (!registration_error_.empty()) return {Result::kUnavailable, registration_error_};
    if (phone_->state() != CallState::kIdle) {
      return {Result::kUnavailable, "a call with " + name_for(phone_->peer()) + " is going on"};
    }
    // Before dialling: the first events may come before dial() returns.
    events_.clear();
    following_ = true;
    answered_ = false;
    emergency_ = false;
    uri_ = uri;
    name_ = name;
  }
  const std::string refused = phone_->dial(uri);
  if (refused.empty()) return {};
  std::lock_guard lock(mutex_);
  following_ = false;
  return {Result::kUnavailable, refused};
}

bool PhoneLink::hang_up() {
  {
    std::lock_guard lock(mutex_);
    following_ = false;
  }
  return phone_->hang_up();
}

bool PhoneLink::answer() {
  if (phone_->state() != CallState::kIncoming) return false;
  return phone_->answer();
}

bool PhoneLink::decline() {
  if (phone_->state() != CallState::kIncoming) return false;
  return phone_->decline();
}

json PhoneLink::state() {
  const CallState now = phone_->state();
  std::lock_guard lock(mutex_);
  if (now == CallState::kIdle) return {{"state", "idle"}, {"number", ""}, {"name", ""}};
  const std::string peer = phone_->peer();
  return {{"state", state_name(now)}, {"number", peer}, {"name", name_for(peer)}};
}

std::optional<json> PhoneLink::wait_event(std::chrono::milliseconds timeout,
                                          const std::function<bool()>& stop) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::unique_lock lock(mutex_);
  for (;;) {
    if (!events_.empty()) {
      json event = std::move(events_.front());
      events_.pop_front();
      return event;
    }
    if (stop && stop()) return std::nullopt;
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) return std::nullopt;
    // "stop" has no way to wake this condition: look at it every 50 ms.
    changed_.wait_for(lock, std::min<std::chrono::steady_clock::duration>(
                                deadline - now, std::chrono::milliseconds(50)));
  }
}

skills::Telephone::Reply PhoneLink::call_for_help(
    std::vector<std::pair<std::string, std::string>> contacts) {
  std::vector<telephony::EmergencyContact> order;
  for (const auto& [name, number] : contacts) {
    const std::string uri = uri_of(number);
    if (uri.empty()) {
      if (hooks_.log_event) {
        hooks_.log_event("emergency", name + "'s number \"" + number + "\" cannot be dialled");
      }
      continue;
    }
    order.push_back({name, uri});
  }
  if (order.empty()) return {Result::kNotFound, "no emergency contact has a number to dial"};
  // Help comes first: a call going on is ended (and its end awaited) before the sequence.
  if (phone_->state() != CallState::kIdle && phone_->hang_up()) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, std::chrono::seconds(5),
                      [&] { return phone_->state() == CallState::kIdle; });
  }
  auto help = std::make_shared<telephony::EmergencyCall>(
      *phone_, std::move(order), [this](const std::string& text) { on_step(text); });
  std::shared_ptr<telephony::EmergencyCall> previous;
  {
    std::lock_guard lock(mutex_);
    events_.clear();
    following_ = false;
    emergency_ = true;
    uri_.clear();
    name_.clear();
    previous = std::exchange(help_, help);
  }
  previous.reset();  // an earlier call for help stops trying
  help->start();
  return {};
}

void PhoneLink::on_step(const std::string& text) {
  if (hooks_.log_event) hooks_.log_event("emergency", text);
  std::lock_guard lock(mutex_);
  if (!emergency_) return;
  events_.push_back({{"event", "emergency_step"}, {"text", text}});
  std::string answered_by;
  const std::string suffix = kAnswered;
  if (text.size() > suffix.size() &&
      text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0) {
    answered_by = text.substr(0, text.size() - suffix.size());
  }
  if (!answered_by.empty() || text == kNobody) {
    events_.push_back({{"event", "emergency_done"}, {"answered_by", answered_by}});
    emergency_ = false;
  }
  changed_.notify_all();
}

void PhoneLink::on_event(const PhoneEvent& event) {
  std::shared_ptr<telephony::EmergencyCall> help;
  std::string say;
  std::pair<std::string, std::string> logged;
  {
    std::lock_guard lock(mutex_);
    help = help_;
    const CallState before = last_state_;
    last_state_ = phone_->state();
    switch (event.kind) {
      case PhoneEvent::Kind::kRinging:
        if (following_) push({{"event", "ringing"}});
        break;
      case PhoneEvent::Kind::kAnswered:
        answered_ = true;
        if (!following_ && before != CallState::kIncoming) {
          uri_ = event.peer_uri;  // a call for help, answered
          name_ = name_for(event.peer_uri);
        }
        if (following_) push({{"event", "answered"}});
        following_ = false;
        break;
      case PhoneEvent::Kind::kEnded: {
        const std::string who = name_for(event.peer_uri.empty() ? uri_ : event.peer_uri);
        if (following_) {
          json e{{"event", end_event(event.end)}};
          if (!event.reason.empty()) e["reason"] = event.reason;
          push(std::move(e));
        } else if (before == CallState::kIncoming && event.end != CallEnd::kHungUp) {
          say = "You missed a call from " + who + ".";
          logged = {"call_missed", say};
        } else if (answered_ && event.end == CallEnd::kRemoteHungUp) {
          say = who + " hung up.";
        } else if (answered_ && event.end == CallEnd::kFailed) {
          say = "The call with " + who + " was cut off: " + event.reason + ".";
        }
        following_ = false;
        answered_ = false;
        break;
      }
      case PhoneEvent::Kind::kIncoming: {
        uri_ = event.peer_uri;
        name_.clear();
        name_ = name_for(event.peer_uri);
        answered_ = false;
        following_ = false;
        last_state_ = CallState::kIncoming;
        say = name_ + " is calling. Say answer or decline.";
        logged = {"call_incoming", name_ + " is calling"};
        break;
      }
      case PhoneEvent::Kind::kRegistered:
        registration_error_.clear();
        break;
      case PhoneEvent::Kind::kRegistrationFailed:
        registration_error_ = event.reason;
        say = "I can't make phone calls: " + event.reason + ".";
        logged = {"phone", event.reason};
        break;
      case PhoneEvent::Kind::kServiceRestarted:
        log(LogLevel::kWarning, "phone", "the phone service (baresip) was restarted");
        logged = {"phone", "the phone service was restarted"};
        break;
    }
  }
  changed_.notify_all();  // call_for_help() may wait for a call to end
  if (help) help->on_phone_event(event);
  if (!logged.first.empty() && hooks_.log_event) hooks_.log_event(logged.first, logged.second);
  if (!say.empty() && hooks_.announce) hooks_.announce(say);
}

}  // namespace marvin::app
