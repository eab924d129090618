// The robot's telephone: places, answers, declines and ends calls through a supervised
// baresip user agent (baresip.h) and tells what happens in the user's terms: ringing,
// answered, busy, not answering, ended, an incoming call.
//
// One call at a time (a second incoming call while one is active is declined as busy).
// "Not answering" is Marvin's own timeout (no_answer_timeout): SIP alone would let the
// other side ring for minutes. Listener calls come from the phone's threads; a listener may
// call back into the phone (dial the next number, hang up): those calls never wait for the
// thread that delivers events.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <optional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "telephony/baresip.h"

namespace marvin::telephony {

enum class CallState { kIdle, kCalling, kRinging, kInCall, kIncoming };
const char* to_string(CallState state);

// How a call ended.
enum class CallEnd {
  kHungUp,          // we ended it (hang up, decline, stop)
  kRemoteHungUp,    // the other side ended an established call
  kBusy,            // the other side declined or is busy (486, 600, 603)
  kNoAnswer,        // nobody answered within the timeout
  kFailed,          // anything else: unreachable, bad number, baresip died
};
const char* to_string(CallEnd end);

struct PhoneEvent {
  enum class Kind {
    kRinging,              // the other side is ringing
    kAnswered,             // the call is established (either direction)
    kEnded,                // `end` says how, `reason` has SIP's words
    kIncoming,             // someone calls: `peer_uri`
    kRegistered,
    kRegistrationFailed,   // `reason` has the registrar's answer
    kServiceRestarted,     // baresip died and runs again
  };
  Kind kind;
  std::string peer_uri;
  CallEnd end = CallEnd::kHungUp;
  std::string reason;
};

class Phone {
 public:
  using Listener = std::function<void(const PhoneEvent&)>;

  Phone(PhoneSettings settings, std::filesystem::path config_dir, Listener listener,
        std::chrono::milliseconds no_answer_timeout = std::chrono::seconds(30));
  ~Phone();  // stop()

  // Starts baresip; throws when it cannot (the message says why).
  void start();
  // Stops baresip, then the thread that delivers events: once it returns the listener is
  // never called again. An owner whose listener uses the phone calls it before destroying
  // the phone (while its pointer to the phone is still valid). Idempotent.
  void stop();
  bool wait_ready(std::chrono::milliseconds timeout) { return baresip_.wait_ready(timeout); }

  // Calls `uri` (sip:...). Empty on success; otherwise why not, in words for the user.
  std::string dial(const std::string& uri);
  // Ends the current call, or declines a ringing incoming one. False when there is none.
  bool hang_up();
  // Answers the ringing incoming call. False when there is none.
  bool answer();
  bool decline() { return hang_up(); }

  CallState state() const;
  std::string peer() const;  // the other side of the current call, empty when idle
  // A SIP URI for what the user gave: "sip:..." unchanged; a phone number (digits, spaces,
  // '+', '-', '/') becomes sip:<digits>@<the account's domain>. Empty when it is neither.
  std::string uri_for(const std::string& number_or_uri) const;

  Baresip& baresip() { return baresip_; }

 private:
  void on_baresip_event(const BaresipEvent& event);  // supervisor thread
  void deliver_loop();                                // the listener's thread
  void emit(PhoneEvent event);                        // with mutex_ held
  void end_call(CallEnd end, const std::string& reason);  // with mutex_ held

  Listener listener_;
  const std::chrono::milliseconds no_answer_timeout_;
  Baresip baresip_;

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  CallState state_ = CallState::kIdle;
  std::string peer_;
  std::string call_id_;
  bool hang_up_requested_ = false;
  // baresip registers before its control socket is up: once connected, ask how that went.
  bool check_registration_ = false;
  std::chrono::steady_clock::time_point no_answer_at_;
  std::deque<PhoneEvent> queue_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace marvin::telephony
