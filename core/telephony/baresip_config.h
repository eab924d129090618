// The configuration directory Marvin writes for its baresip user agent: `config` (modules,
// SIP listen address, audio devices, ctrl_tcp port) and `accounts` (one SIP account).
//
// Marvin owns these files: they are rewritten at every start from Marvin's own settings,
// so the user never edits baresip's files.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace marvin::telephony {

struct PhoneSettings {
  // The robot's SIP address, "sip:marvin@127.0.0.1:5070" (peer to peer, no registrar) or
  // "sip:robot@sip.example.org".
  std::string account_uri;
  // The registrar's URI ("sip:sip.example.org"); empty: no registration (regint=0),
  // calls go straight to the peer's address.
  std::string registrar;
  std::string auth_user;
  std::string auth_password;
  // Where baresip listens for SIP; port 0 picks a free port (and the port above it,
  // which baresip also binds for SIP over TLS).
  std::string listen_address = "127.0.0.1";
  int sip_port = 0;

  enum class Audio {
    kFiles,  // simulated robot and tests: the call's audio from a WAV file, to WAV files
    kAlsa,   // the real robot's sound card
  };
  Audio audio = Audio::kFiles;
  // kFiles: the WAV file played to the other side (8 kHz mono 16-bit); the call ends when
  // it ends (baresip 1.0's aufile does not loop). Empty: a 440 Hz tone (ausine).
  std::filesystem::path audio_in;
  // kFiles: where the other side's audio is recorded (sndfile module, one
  // dump-<time>-dec.wav per call; also baresip's working directory).
  std::filesystem::path record_dir;
  std::string alsa_device = "default";
  // Answer every incoming call at once (the test peer; never the robot).
  bool auto_answer = false;
  // More users this agent answers as, at the account's address (the simulated other end
  // of `marvin run --sim`: "anna", "brown", "0123456789"); baresip refuses calls to users it
  // has no account for (404).
  std::vector<std::string> answer_as;

  std::filesystem::path baresip_program = "/usr/bin/baresip";
  std::filesystem::path module_path = "/usr/lib/baresip/modules";
};

// A 127.0.0.1 TCP port nobody listens on now (the kernel's choice); `pair` also requires
// port+1 to be free (baresip binds SIP over TLS there).
int pick_free_port(bool pair = false);

// Writes `dir`/config and `dir`/accounts. `sip_port` and `ctrl_port` are the chosen ports.
// Throws std::runtime_error naming the setting that is wrong.
void write_baresip_config(const PhoneSettings& settings, int sip_port, int ctrl_port,
                          const std::filesystem::path& dir);

}  // namespace marvin::telephony
