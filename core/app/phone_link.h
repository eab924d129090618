// The robot's telephone (core/telephony: a supervised baresip) as the Robot API's phone
// calls see it (skills::Telephone), plus what the host itself says and logs about calls.
//
// Who says what: the skill that placed a call reads its progress (ringing, answered, busy,
// not answering) from wait_event() and says it. The host says what no skill is waiting for:
// "Anna is calling. Say answer or decline.", "Anna hung up.", "You missed a call from
// Anna.", a refused registration, a restarted phone service. A call for help runs here
// (telephony::EmergencyCall); every step goes to the event log and the message bus
// (`log_event`) and to the skill as an "emergency_step" event.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "skills/telephone.h"
#include "telephony/emergency_call.h"
#include "telephony/phone.h"

namespace marvin::app {

struct PhoneLinkHooks {
  // Speaks a sentence nobody asked for (the host loop's say). Any thread.
  std::function<void(const std::string&)> announce;
  // Writes (kind, sentence) to the event log and the bus ("emergency", "call_missed").
  std::function<void(const std::string&, const std::string&)> log_event;
  // The contact name for a SIP address or number ("" when none matches).
  std::function<std::string(const std::string&)> name_of;
  // Rewrites a SIP address before dialling (the simulated robot: sip:anna@sim -> the
  // simulated other end on 127.0.0.1); empty: as is.
  std::function<std::string(const std::string&)> route;
};

class PhoneLink final : public skills::Telephone {
 public:
  PhoneLink(telephony::PhoneSettings settings, std::filesystem::path config_dir,
            PhoneLinkHooks hooks,
            std::chrono::milliseconds no_answer_timeout = std::chrono::seconds(30));
  ~PhoneLink() override;

  // Starts baresip; throws with the reason when it cannot.
  void start();
  bool wait_ready(std::chrono::milliseconds timeout) { return phone_->wait_ready(timeout); }
  telephony::Phone& phone() { return *phone_; }

  Reply dial(const std::string& number, const std::string& name) override;
  bool hang_up() override;
  bool answer() override;
  bool decline() override;
  nlohmann::json state() override;
  std::optional<nlohmann::json> wait_event(std::chrono::milliseconds timeout,
                                           const std::function<bool()>& stop) override;
  Reply call_for_help(std::vector<std::pair<std::string, std::string>> contacts) override;

 private:
  void on_event(const telephony::PhoneEvent& event);  // the phone's delivery thread
  void on_step(const std::string& text);              // the emergency call's thread
  void push(nlohmann::json event);                    // with mutex_ held
  std::string uri_of(const std::string& number) const;
  std::string name_for(const std::string& uri);       // with mutex_ held

  PhoneLinkHooks hooks_;
  std::unique_ptr<telephony::Phone> phone_;

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<nlohmann::json> events_;  // for the skill that placed the call
  bool following_ = false;   // a skill placed the current call and waits for its progress
  bool emergency_ = false;   // a call for help runs: its steps go to the skill
  bool answered_ = false;    // the current call was established
  telephony::CallState last_state_ = telephony::CallState::kIdle;
  std::string uri_;          // the current call's other side
  std::string name_;         // ... as the user knows them
  std::string registration_error_;
  std::shared_ptr<telephony::EmergencyCall> help_;
};

}  // namespace marvin::app
