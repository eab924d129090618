#include "app/host_phone.h"

#include <unistd.h>

#include <cctype>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/log.h"
#include "skills/api_json.h"

namespace marvin::app {
namespace {

using nlohmann::json;

struct SipParts {
  std::string user, host, port;
};

SipParts parts(const std::string& uri) {
  SipParts p;
  if (uri.rfind("sip:", 0) != 0) return p;
  const auto at = uri.find('@');
  if (at == std::string::npos) return p;
  p.user = uri.substr(4, at - 4);
  std::string rest = uri.substr(at + 1);
  rest = rest.substr(0, rest.find(';'));
  const auto colon = rest.find(':');
  p.host = rest.substr(0, colon);
  if (colon != std::string::npos) p.port = rest.substr(colon + 1);
  return p;
}

std::string digits_of(const std::string& number) {
  std::string d;
  for (char c : number) {
    if (std::isdigit(static_cast<unsigned char>(c)) || (c == '+' && d.empty())) d += c;
  }
  return d;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

constexpr char kSimHost[] = "sim";

}  // namespace

std::string contact_name_for(const std::string& uri, const std::vector<data::Contact>& contacts) {
  const SipParts heard = parts(uri);
  if (heard.user.empty()) return {};
  for (const data::Contact& c : contacts) {
    for (const std::string& sip : c.sip_uris) {
      const SipParts known = parts(sip);
      if (lower(known.user) == lower(heard.user) &&
          (known.host == heard.host || known.host == kSimHost)) {
        return c.name;
      }
    }
    const std::string digits = digits_of(heard.user);
    if (digits.size() < 3 || digits != heard.user) continue;
    for (const std::string& number : c.phone_numbers) {
      if (digits_of(number) == digits) return c.name;
    }
  }
  return {};
}

telephony::PhoneSettings load_phone_config(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the phone configuration");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(file.string() + ": not JSON at byte " + std::to_string(e.byte));
  }
  auto fail = [&](const std::string& field, const std::string& what) -> std::runtime_error {
    return std::runtime_error(file.string() + ": " + field + ": " + what);
  };
  if (!j.is_object()) throw fail("$", "expected an object");
  auto text = [&](const char* field, bool required) -> std::string {
    auto it = j.find(field);
    if (it == j.end()) {
      if (required) throw fail(field, "missing (expected a string)");
      return {};
    }
    if (!it->is_string()) throw fail(field, "expected a string, got " + it->dump());
    return it->get<std::string>();
  };
  telephony::PhoneSettings s;
  s.account_uri = text("account", true);
  if (s.account_uri.rfind("sip:", 0) != 0 || s.account_uri.find('@') == std::string::npos) {
    throw fail("account", "expected a SIP address like sip:robot@sip.example.org, got \"" +
                              s.account_uri + "\"");
  }
  s.registrar = text("registrar", false);
  if (!s.registrar.empty() && s.registrar.rfind("sip:", 0) != 0) {
    throw fail("registrar", "expected a SIP URI like sip:sip.example.org, got \"" +
                                s.registrar + "\"");
  }
  s.auth_user = text("user", false);
  s.auth_password = text("password", false);
  if (std::string device = text("audio_device", false); !device.empty()) s.alsa_device = device;
  if (auto it = j.find("sip_port"); it != j.end()) {
    if (!it->is_number_integer() || it->get<int>() < 0 || it->get<int>() > 65534) {
      throw fail("sip_port", "expected a port number 0..65534 (0: a free one), got " + it->dump());
    }
    s.sip_port = it->get<int>();
  }
  return s;
}

HostPhone::HostPhone(PhoneOptions options, data::PersonalData& data, PhoneLinkHooks hooks)
    : options_(std::move(options)) {
  // On stderr, not the transcript: the conversation stays the same with or without a phone.
  auto warn = [](const std::string& text) { log(LogLevel::kWarning, "phone", text); };
  const std::filesystem::path program = options_.settings.baresip_program;
  if (::access(program.c_str(), X_OK) != 0) {
    warn(program.string() + " is not installed (apt-get install baresip-core); running "
         "without a phone");
    return;
  }
  dir_ = options_.dir;
  if (dir_.empty()) {
    std::string pattern = (std::filesystem::temp_directory_path() / "marvin-phone-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      warn("cannot create a directory for baresip; running without a phone");
      return;
    }
    dir_ = pattern;
    own_dir_ = true;
  }
  try {
    if (!options_.simulated_people.empty()) {
      start_simulated_peer(data);
      // Its port is read at each call: it changes when another program took it (baresip.h).
      telephony::Baresip* peer = peer_.get();
      // "@sim" and numbers dialled at Marvin's own address go to the simulated other end.
      hooks.route = [peer](const std::string& uri) {
        SipParts p = parts(uri);
        if (p.host == kSimHost || (p.host == "127.0.0.1" && p.port.empty())) {
          return "sip:" + p.user + "@127.0.0.1:" + std::to_string(peer->sip_port());
        }
        return uri;
      };
    }
    if (!hooks.name_of) {
      hooks.name_of = [&data](const std::string& uri) {
        return contact_name_for(uri, data.list_contacts());
      };
    }
    telephony::PhoneSettings settings = options_.settings;
    if (settings.record_dir.empty()) settings.record_dir = dir_ / "recordings";
    std::filesystem::create_directories(settings.record_dir);
    link_ = std::make_unique<PhoneLink>(settings, dir_ / "marvin", std::move(hooks),
                                        options_.no_answer_timeout);
    link_->start();
    if (!link_->wait_ready(std::chrono::seconds(10))) {
      throw std::runtime_error("baresip did not start within 10 s (its files: " +
                               (dir_ / "marvin").string() + ")");
    }
    log(LogLevel::kInfo, "phone",
        "ready, " + settings.account_uri.substr(0, settings.account_uri.rfind('@')) +
            "@127.0.0.1:" + std::to_string(link_->phone().baresip().sip_port()));
  } catch (const std::exception& e) {
    link_.reset();
    peer_.reset();
    warn(std::string(e.what()) + "; running without a phone");
  }
}

HostPhone::~HostPhone() {
  link_.reset();
  peer_.reset();
  if (own_dir_) {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
}

void HostPhone::start_simulated_peer(data::PersonalData& data) {
  std::ifstream in(options_.simulated_people);
  if (!in) throw std::runtime_error("cannot read " + options_.simulated_people.string());
  json people;
  try {
    people = json::parse(in);
  } catch (const json::parse_error& e) {
    throw std::runtime_error(options_.simulated_people.string() + ": not JSON at byte " +
                             std::to_string(e.byte));
  }
  telephony::PhoneSettings peer;
  peer.account_uri = "sip:sim@127.0.0.1";
  peer.auto_answer = true;
  peer.baresip_program = options_.settings.baresip_program;
  peer.module_path = options_.settings.module_path;
  peer.record_dir = dir_ / "simulated-other-end";
  std::filesystem::create_directories(peer.record_dir);
  std::vector<std::string> added;
  const json list = people.value("contacts", json::array());
  for (std::size_t i = 0; i < list.size(); ++i) {
    data::Contact contact;
    try {
      contact = skills::contact_from_json(list[i]);
    } catch (const std::exception& e) {
      throw std::runtime_error(options_.simulated_people.string() + ": $.contacts[" +
                               std::to_string(i) + "]: " + e.what());
    }
    for (const std::string& sip : contact.sip_uris) {
      if (parts(sip).host == kSimHost) peer.answer_as.push_back(parts(sip).user);
    }
    for (const std::string& number : contact.phone_numbers) {
      peer.answer_as.push_back(digits_of(number));
    }
    bool known = false;
    for (const data::Contact& c : data.find_contacts(contact.name)) known |= c.name == contact.name;
    if (!known) {
      data.add_contact(contact);
      added.push_back(contact.name);
    }
  }
  if (!added.empty()) {
    std::string names;
    for (const std::string& n : added) names += (names.empty() ? "" : ", ") + n;
    log(LogLevel::kInfo, "phone", "added the simulated contacts " + names);
  }
  peer_ = std::make_unique<telephony::Baresip>(peer, dir_ / "simulated-other-end-config",
                                               [](const telephony::BaresipEvent&) {});
  peer_->start();
  if (!peer_->wait_ready(std::chrono::seconds(10))) {
    throw std::runtime_error("the simulated other end (baresip) did not start");
  }
}

}  // namespace marvin::app
