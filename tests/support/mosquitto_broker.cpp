#include "support/mosquitto_broker.h"

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <stdexcept>

namespace marvin::test_support {

int free_tcp_port() {
  int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw std::runtime_error("free_tcp_port: socket() failed");
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    ::close(fd);
    throw std::runtime_error("free_tcp_port: cannot bind to 127.0.0.1");
  }
  ::close(fd);
  return ntohs(a.sin_port);
}

std::optional<std::string> MosquittoBroker::binary() {
  for (const char* p : {"/usr/sbin/mosquitto", "/usr/bin/mosquitto", "/usr/local/sbin/mosquitto"}) {
    if (::access(p, X_OK) == 0) return std::string(p);
  }
  return std::nullopt;
}

MosquittoBroker::MosquittoBroker() {
  if (!binary()) {
    throw std::runtime_error("mosquitto is not installed (Debian package mosquitto)");
  }
  port_ = free_tcp_port();
  write_text(dir_ / "mosquitto.conf",
             "listener " + std::to_string(port_) + " 127.0.0.1\n"
             "allow_anonymous true\n"
             "persistence false\n"
             "log_dest stderr\n"
             "log_type error\nlog_type warning\nlog_type notice\nlog_type information\n");
  start();
}

MosquittoBroker::~MosquittoBroker() { kill(); }

void MosquittoBroker::start() {
  ChildOptions options;
  options.in = ChildStream::kNull;
  options.err = ChildStream::kNull;
  // mosquitto's log goes to stderr unbuffered (stdout would be block-buffered in a pipe);
  // exec keeps the broker the child, so kill() reaches it.
  process_ = std::make_unique<ChildProcess>(ChildProcess::shell(
      "exec " + *binary() + " -c '" + (dir_ / "mosquitto.conf").string() + "' 2>&1", options));
  // "mosquitto version 2.0.11 running" follows the listener being opened.
  process_->wait_for_line("mosquitto running on port " + std::to_string(port_),
                          [](const std::string& line) {
                            return line.find(" running") != std::string::npos;
                          });
}

void MosquittoBroker::kill() {
  if (!process_) return;
  process_->stop(SIGKILL);
  process_.reset();
}

void MosquittoBroker::restart() {
  kill();
  start();
}

}  // namespace marvin::test_support
