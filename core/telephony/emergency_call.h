// "Call for help": no confirmation question; calls the emergency contacts in their order
// until one answers.
//
// Each attempt ends when the contact answers (done), declines or is busy, does not answer
// within the phone's timeout, or the call fails; then the next contact is called. Every step
// is reported to `on_step` (the caller writes it to the event log and may say it). When the
// last contact did not answer, the sequence ends unanswered. Runs on its own thread; the
// Phone's listener must forward its events to on_phone_event().
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "telephony/phone.h"

namespace marvin::telephony {

struct EmergencyContact {
  std::string name;  // "Anna"
  std::string uri;   // sip:...
};

class EmergencyCall {
 public:
  // `text` is a sentence for the event log: "Calling Anna for help", "Anna did not answer
  // (busy)", "Anna answered the emergency call", "Nobody answered the emergency call".
  using StepHandler = std::function<void(const std::string& text)>;

  EmergencyCall(Phone& phone, std::vector<EmergencyContact> contacts, StepHandler on_step);
  ~EmergencyCall();  // stops trying (a call in progress stays up)

  void start();
  void on_phone_event(const PhoneEvent& event);
  // Waits until someone answered (their name) or everybody was tried (empty).
  std::optional<std::string> wait(std::chrono::milliseconds timeout);

 private:
  void run();

  Phone& phone_;
  const std::vector<EmergencyContact> contacts_;
  const StepHandler on_step_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<PhoneEvent> outcome_;  // of the current attempt: answered or ended
  bool finished_ = false;
  bool cancelled_ = false;
  std::string answered_by_;
  std::thread thread_;
};

}  // namespace marvin::telephony
