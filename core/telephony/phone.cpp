#include "telephony/phone.h"

#include <cctype>

#include "common/log.h"

namespace marvin::telephony {

const char* to_string(CallState state) {
  switch (state) {
    case CallState::kIdle: return "idle";
    case CallState::kCalling: return "calling";
    case CallState::kRinging: return "ringing";
    case CallState::kInCall: return "in call";
    case CallState::kIncoming: return "incoming";
  }
  return "?";
}

const char* to_string(CallEnd end) {
  switch (end) {
    case CallEnd::kHungUp: return "hung up";
    case CallEnd::kRemoteHungUp: return "the other side hung up";
    case CallEnd::kBusy: return "busy";
    case CallEnd::kNoAnswer: return "no answer";
    case CallEnd::kFailed: return "failed";
  }
  return "?";
}

namespace {

// baresip 1.0 registers before its control socket is up and its REGISTER_FAIL event is
// lost; "reginfo" keeps only "ERR" and the server's name, not the status code (the code is
// in baresip's log). "reginfo" answers with a table: "> sip:marvin@host  \x1b[31mERR\x1b[;m 501 Not
// Implemented (...) Expires 0s" or "... OK ...". Colour codes removed; nullopt while the
// registration is still under way (the REGISTER_* event follows).
std::optional<PhoneEvent> registration_from_reginfo(const std::string& registrar,
                                                    const std::string& text) {
  std::string plain;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\x1b') {
      while (i < text.size() && text[i] != 'm') ++i;
      continue;
    }
    plain += text[i];
  }
  if (const auto err = plain.find(" ERR "); err != std::string::npos) {
    std::string detail = plain.substr(err + 5);
    detail = detail.substr(0, detail.find('\n'));
    while (!detail.empty() && detail.front() == ' ') detail.erase(0, 1);
    const std::string reason = registrar + " refused the registration (" + detail + ")";
    return PhoneEvent{PhoneEvent::Kind::kRegistrationFailed, {}, CallEnd::kHungUp, reason};
  }
  if (plain.find(" OK ") != std::string::npos) {
    return PhoneEvent{PhoneEvent::Kind::kRegistered, {}, CallEnd::kHungUp, {}};
  }
  return std::nullopt;
}

}  // namespace

Phone::Phone(PhoneSettings settings, std::filesystem::path config_dir, Listener listener,
             std::chrono::milliseconds no_answer_timeout)
    : listener_(std::move(listener)),
      no_answer_timeout_(no_answer_timeout),
      baresip_(std::move(settings), std::move(config_dir),
               [this](const BaresipEvent& event) { on_baresip_event(event); }) {}

Phone::~Phone() { stop(); }

void Phone::stop() {
  // baresip first: no more events once it is gone; then the delivery thread.
  baresip_.stop();
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Phone::start() {
  thread_ = std::thread([this] { deliver_loop(); });
  baresip_.start();
}

CallState Phone::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

std::string Phone::peer() const {
  std::lock_guard lock(mutex_);
  return peer_;
}

std::string Phone::uri_for(const std::string& given) const {
  if (given.rfind("sip:", 0) == 0) return given;
  std::string digits;
  for (char c : given) {
    if (std::isdigit(static_cast<unsigned char>(c)) || (c == '+' && digits.empty())) {
      digits += c;
    } else if (c != ' ' && c != '-' && c != '/' && c != '(' && c != ')' && c != '.') {
      return {};
    }
  }
  if (digits.empty() || digits == "+") return {};
  const std::string& account = baresip_.settings().account_uri;
  const auto at = account.find('@');
  if (at == std::string::npos) return {};
  return "sip:" + digits + account.substr(at);
}

std::string Phone::dial(const std::string& uri) {
  {
    std::lock_guard lock(mutex_);
    if (state_ != CallState::kIdle) return "I am already on a call.";
    state_ = CallState::kCalling;
    peer_ = uri;
    call_id_.clear();
    hang_up_requested_ = false;
    no_answer_at_ = std::chrono::steady_clock::now() + no_answer_timeout_;
  }
  changed_.notify_all();
  const CommandResult result = baresip_.command("dial", uri);
  if (result.ok) return {};
  std::lock_guard lock(mutex_);
  if (state_ == CallState::kCalling) {
    state_ = CallState::kIdle;
    peer_.clear();
  }
  log(LogLevel::kWarning, "phone", "dial " + uri + " failed: " + result.data);
  return "The phone could not call " + uri + ": " + result.data;
}

bool Phone::hang_up() {
  {
    std::lock_guard lock(mutex_);
    if (state_ == CallState::kIdle) return false;
    hang_up_requested_ = true;
  }
  return baresip_.command("hangup").ok;
}

bool Phone::answer() {
  {
    std::lock_guard lock(mutex_);
    if (state_ != CallState::kIncoming) return false;
  }
  return baresip_.command("accept").ok;
}

void Phone::emit(PhoneEvent event) {
  queue_.push_back(std::move(event));
  changed_.notify_all();
}

void Phone::end_call(CallEnd end, const std::string& reason) {
  PhoneEvent event{PhoneEvent::Kind::kEnded, peer_, end, reason};
  state_ = CallState::kIdle;
  peer_.clear();
  call_id_.clear();
  hang_up_requested_ = false;
  emit(std::move(event));
}

void Phone::on_baresip_event(const BaresipEvent& e) {
  std::lock_guard lock(mutex_);
  const bool ours = call_id_.empty() || e.call_id.empty() || e.call_id == call_id_;
  if (e.type == "CALL_INCOMING") {
    if (state_ != CallState::kIdle) {
      log(LogLevel::kInfo, "phone", "second call from " + e.peer_uri + " while busy (ignored)");
      return;
    }
    state_ = CallState::kIncoming;
    peer_ = e.peer_uri;
    call_id_ = e.call_id;
    hang_up_requested_ = false;
    emit({PhoneEvent::Kind::kIncoming, peer_, CallEnd::kHungUp, {}});
  } else if (e.type == "CALL_RINGING" && ours) {
    if (call_id_.empty()) call_id_ = e.call_id;
    if (state_ == CallState::kCalling) {
      state_ = CallState::kRinging;
      emit({PhoneEvent::Kind::kRinging, peer_, CallEnd::kHungUp, {}});
    }
  } else if (e.type == "CALL_ESTABLISHED" && ours) {
    if (state_ != CallState::kIdle && state_ != CallState::kInCall) {
      state_ = CallState::kInCall;
      emit({PhoneEvent::Kind::kAnswered, peer_, CallEnd::kHungUp, {}});
    }
  } else if (e.type == "CALL_CLOSED" && ours) {
    if (state_ == CallState::kIdle) return;
    CallEnd end = CallEnd::kFailed;
    const std::string code = e.param.substr(0, 3);
    if (hang_up_requested_) {
      end = std::chrono::steady_clock::now() >= no_answer_at_ &&
                    (state_ == CallState::kCalling || state_ == CallState::kRinging)
                ? CallEnd::kNoAnswer
                : CallEnd::kHungUp;
    } else if (code == "486" || code == "600" || code == "603") {
      end = CallEnd::kBusy;
    } else if (state_ == CallState::kInCall || state_ == CallState::kIncoming) {
      end = CallEnd::kRemoteHungUp;
    } else if (code == "408" || code == "480") {
      end = CallEnd::kNoAnswer;
    }
    end_call(end, e.param);
  } else if (e.type == "REGISTER_OK") {
    emit({PhoneEvent::Kind::kRegistered, {}, CallEnd::kHungUp, e.param});
  } else if (e.type == "REGISTER_FAIL") {
    emit({PhoneEvent::Kind::kRegistrationFailed, {}, CallEnd::kHungUp,
          baresip_.settings().registrar + " refused the registration (" + e.param + ")"});
  } else if (e.type == "MARVIN_EXITED") {
    if (state_ != CallState::kIdle) end_call(CallEnd::kFailed, "the phone service stopped");
  } else if (e.type == "MARVIN_READY") {
    if (!baresip_.settings().registrar.empty()) {
      check_registration_ = true;
      changed_.notify_all();
    }
    if (baresip_.restarts() > 0) {
      emit({PhoneEvent::Kind::kServiceRestarted, {}, CallEnd::kHungUp, {}});
    }
  }
}

void Phone::deliver_loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    const bool waiting_for_answer =
        (state_ == CallState::kCalling || state_ == CallState::kRinging) && !hang_up_requested_;
    if (queue_.empty() && !stopping_ && !check_registration_) {
      if (waiting_for_answer) {
        changed_.wait_until(lock, no_answer_at_);
      } else {
        changed_.wait(lock);
      }
    }
    while (!queue_.empty()) {
      PhoneEvent event = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      if (listener_) listener_(event);
      lock.lock();
    }
    if (stopping_) return;
    if (check_registration_) {
      check_registration_ = false;
      lock.unlock();
      const CommandResult info = baresip_.command("reginfo");
      lock.lock();
      if (auto event = registration_from_reginfo(baresip_.settings().registrar, info.data)) emit(std::move(*event));
      continue;
    }
    if ((state_ == CallState::kCalling || state_ == CallState::kRinging) && !hang_up_requested_ &&
        std::chrono::steady_clock::now() >= no_answer_at_) {
      hang_up_requested_ = true;
      log(LogLevel::kInfo, "phone", peer_ + " is not answering; hanging up");
      lock.unlock();
      baresip_.command("hangup");
      lock.lock();
    }
  }
}

}  // namespace marvin::telephony
