#include "telephony/emergency_call.h"

namespace marvin::telephony {

EmergencyCall::EmergencyCall(Phone& phone, std::vector<EmergencyContact> contacts,
                             StepHandler on_step)
    : phone_(phone), contacts_(std::move(contacts)), on_step_(std::move(on_step)) {}

EmergencyCall::~EmergencyCall() {
  {
    std::lock_guard lock(mutex_);
    cancelled_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void EmergencyCall::start() { thread_ = std::thread([this] { run(); }); }

void EmergencyCall::on_phone_event(const PhoneEvent& event) {
  if (event.kind != PhoneEvent::Kind::kAnswered && event.kind != PhoneEvent::Kind::kEnded) return;
  std::lock_guard lock(mutex_);
  if (!outcome_) outcome_ = event;
  changed_.notify_all();
}

std::optional<std::string> EmergencyCall::wait(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  if (!changed_.wait_for(lock, timeout, [&] { return finished_; })) return std::nullopt;
  return answered_by_;
}

void EmergencyCall::run() {
  for (const EmergencyContact& contact : contacts_) {
    {
      std::lock_guard lock(mutex_);
      if (cancelled_) return;
      outcome_.reset();
    }
    on_step_("Calling " + contact.name + " for help");
    const std::string refused = phone_.dial(contact.uri);
    if (!refused.empty()) {
      on_step_(contact.name + " could not be called: " + refused);
      continue;
    }
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return outcome_.has_value() || cancelled_; });
    if (cancelled_) return;
    if (outcome_->kind == PhoneEvent::Kind::kAnswered) {
      answered_by_ = contact.name;
      finished_ = true;
      lock.unlock();
      on_step_(contact.name + " answered the emergency call");
      changed_.notify_all();
      return;
    }
    const std::string why = to_string(outcome_->end);
    lock.unlock();
    on_step_(contact.name + " did not answer (" + why + ")");
  }
  on_step_("Nobody answered the emergency call");
  std::lock_guard lock(mutex_);
  finished_ = true;
  changed_.notify_all();
}

}  // namespace marvin::telephony
