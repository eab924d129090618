#include "telephony/baresip_config.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <stdexcept>

namespace marvin::telephony {
namespace {

bool port_free(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return false;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return ok;
}

int kernel_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw std::runtime_error("phone: cannot open a socket to find a free port");
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  int port = -1;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size) == 0) {
    port = ntohs(address.sin_port);
  }
  ::close(fd);
  if (port < 0) throw std::runtime_error("phone: no free TCP port on 127.0.0.1");
  return port;
}

void check_line(const std::string& value, const char* field) {
  if (value.find_first_of("\r\n<>;\"") != std::string::npos) {
    throw std::runtime_error(std::string("phone settings: ") + field +
                             " must not contain line breaks, '<', '>', ';' or '\"': " + value);
  }
}

}  // namespace

int pick_free_port(bool pair) {
  for (int attempt = 0; attempt < 50; ++attempt) {
    const int port = kernel_port();
    if (!pair || (port < 65535 && port_free(port + 1))) return port;
  }
  throw std::runtime_error("phone: no two neighbouring free TCP ports on 127.0.0.1");
}

void write_baresip_config(const PhoneSettings& s, int sip_port, int ctrl_port,
                          const std::filesystem::path& dir) {
  if (s.account_uri.rfind("sip:", 0) != 0 || s.account_uri.find('@') == std::string::npos) {
    throw std::runtime_error("phone settings: account must be a SIP URI like "
                             "sip:marvin@example.org, got '" + s.account_uri + "'");
  }
  check_line(s.account_uri, "account");
  check_line(s.registrar, "registrar");
  check_line(s.auth_user, "user");
  check_line(s.auth_password, "password");
  check_line(s.listen_address, "listen address");
  if (!s.registrar.empty() && s.registrar.rfind("sip:", 0) != 0) {
    throw std::runtime_error("phone settings: registrar must be a SIP URI like "
                             "sip:sip.example.org, got '" + s.registrar + "'");
  }
  std::filesystem::create_directories(dir);
  std::ofstream config(dir / "config", std::ios::trunc);
  config << "# Written by Marvin at every start (core/telephony); edits are lost.\n"
         << "poll_method poll\n"
         << "sip_listen " << s.listen_address << ':' << sip_port << "\n"
         // Loopback only: otherwise baresip offers the first network card's address for the
         // call's audio (RTP), and the media would leave 127.0.0.1.
         << (s.listen_address == "127.0.0.1" ? "net_interface 127.0.0.1\n" : "")
         << "sip_verify_server no\n"
         << "module_path " << s.module_path.string() << "\n"
         << "module g711.so\n";
  if (s.audio == PhoneSettings::Audio::kFiles) {
    config << "module aufile.so\nmodule ausine.so\nmodule sndfile.so\n";
    if (s.audio_in.empty()) {
      // ausine only produces 48 kHz stereo; baresip resamples it to the codec's rate.
      config << "audio_source ausine,440\nausrc_srate 48000\nausrc_channels 2\n";
    } else {
      check_line(s.audio_in.string(), "audio in");
      config << "audio_source aufile," << s.audio_in.string() << "\n";
    }
    // No file player in baresip 1.0: the sndfile filter records what is heard; the player
    // itself is a device that does not exist, which baresip tolerates.
    config << "audio_player aufile,none\naudio_alert aufile,none\n";
  } else {
    check_line(s.alsa_device, "alsa device");
    config << "module alsa.so\n"
           << "audio_source alsa," << s.alsa_device << "\n"
           << "audio_player alsa," << s.alsa_device << "\n"
           << "audio_alert alsa," << s.alsa_device << "\n";
  }
  config << "module_app account.so\nmodule_app menu.so\nmodule_app ctrl_tcp.so\n"
         << "ctrl_tcp_listen 127.0.0.1:" << ctrl_port << "\n";
  std::ofstream accounts(dir / "accounts", std::ios::trunc);
  accounts << '<' << s.account_uri << '>';
  if (s.registrar.empty()) {
    accounts << ";regint=0";
  } else {
    // baresip registers with the account's domain; a registrar elsewhere is reached as
    // an outbound proxy.
    const std::string domain = "sip:" + s.account_uri.substr(s.account_uri.find('@') + 1);
    if (domain != s.registrar) accounts << ";outbound=\"" << s.registrar << '"';
    accounts << ";regint=600";
  }
  if (!s.auth_user.empty()) accounts << ";auth_user=" << s.auth_user;
  if (!s.auth_password.empty()) accounts << ";auth_pass=" << s.auth_password;
  accounts << ";answermode=" << (s.auto_answer ? "auto" : "manual") << "\n";
  const std::string domain = s.account_uri.substr(s.account_uri.find('@'));
  for (const std::string& user : s.answer_as) {
    check_line(user, "answer as");
    if (user.empty() || user.find_first_of("@: ") != std::string::npos) {
      throw std::runtime_error("phone settings: answer as: '" + user +
                               "' is not a SIP user name (no '@', ':' or spaces)");
    }
    accounts << "<sip:" << user << domain << ">;regint=0;answermode="
             << (s.auto_answer ? "auto" : "manual") << "\n";
  }
  if (!config || !accounts) {
    throw std::runtime_error("phone: cannot write baresip's configuration in " + dir.string());
  }
}

}  // namespace marvin::telephony
