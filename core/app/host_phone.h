// The host's telephone: Marvin's own baresip (app/phone_link.h) and, in the simulated
// robot, the other end of its calls.
//
// `marvin run --sim`: Marvin's account is sip:marvin@127.0.0.1 (peer to peer, no
// registrar), the call's audio is a tone to and recordings from files (aufile/sndfile, no
// sound card), and a second baresip on 127.0.0.1 answers at once as the people of
// examples/worlds/phone.json; they are added to the contacts when no contact of that name
// exists. Their addresses are written "sip:anna@sim": the host sends "@sim" (and numbers
// dialled at the account's own address) to that simulated other end. Nothing leaves
// 127.0.0.1. Without baresip installed the robot runs without a phone and says so.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "app/phone_link.h"
#include "data/personal_data.h"
#include "telephony/baresip.h"

namespace marvin::app {

struct PhoneOptions {
  // Marvin's account, SIP port and audio. The simulated robot ignores the account.
  telephony::PhoneSettings settings;
  // Where baresip's configuration and recordings go; empty: a new temporary directory.
  std::filesystem::path dir;
  std::chrono::milliseconds no_answer_timeout{std::chrono::seconds(30)};
  // The simulated other end answers as the people in this file (examples/worlds/phone.json:
  // {"contacts": [<contact as contacts_add takes it>, ...]}); empty: no simulated other end.
  std::filesystem::path simulated_people;
};

class HostPhone {
 public:
  // Starts the phone (and the simulated other end). Never throws: without a working
  // baresip, link() is null and the log (stderr) says why.
  HostPhone(PhoneOptions options, data::PersonalData& data, PhoneLinkHooks hooks);
  ~HostPhone();

  PhoneLink* link() { return link_.get(); }
  // The simulated other end (null outside the simulated robot).
  telephony::Baresip* simulated_peer() { return peer_.get(); }

 private:
  void start_simulated_peer(data::PersonalData& data);

  PhoneOptions options_;
  std::filesystem::path dir_;
  bool own_dir_ = false;
  std::unique_ptr<telephony::Baresip> peer_;
  std::unique_ptr<PhoneLink> link_;
};

// The robot's own phone account, from a JSON file (`marvin run --phone-config FILE`):
//   {"account": "sip:robot@sip.example.org", "registrar": "sip:sip.example.org",
//    "user": "robot", "password": "...", "sip_port": 5060, "audio_device": "default"}
// Only "account" is required (no registrar: peer to peer). Throws std::runtime_error
// "<file>: <field>: <what was expected>" for a missing file, bad JSON or a bad field.
telephony::PhoneSettings load_phone_config(const std::filesystem::path& file);

// The contact name for a SIP address or number among `contacts` ("" when none).
// "sip:anna@127.0.0.1:5062" matches a contact's "sip:anna@127.0.0.1" and "sip:anna@sim";
// "sip:0301555@..." matches a phone number with those digits.
std::string contact_name_for(const std::string& uri, const std::vector<data::Contact>& contacts);

}  // namespace marvin::app
