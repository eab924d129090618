// A real mosquitto broker for a test or a benchmark: started on 127.0.0.1 on a free port
// with its own config in a temporary directory, ready once it logs that it runs (read from
// its output, never by sleeping), killed and reaped when the object goes. kill() and
// restart() (same port) play a broker that crashes and comes back.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "support/child_process.h"
#include "support/files.h"

namespace marvin::test_support {

// A TCP port on 127.0.0.1 that was free a moment ago.
int free_tcp_port();

class MosquittoBroker {
 public:
  // Throws std::runtime_error when mosquitto is not installed or does not start.
  MosquittoBroker();
  ~MosquittoBroker();

  int port() const { return port_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  bool running() const { return process_ != nullptr; }

  void kill();     // SIGKILL, as a crash (retained messages are lost: no persistence)
  void restart();  // starts again on the same port, ready when it returns

  // The path of the mosquitto binary, or nullopt when it is not installed.
  static std::optional<std::string> binary();

 private:
  void start();
  TempDir dir_;
  int port_ = 0;
  std::unique_ptr<ChildProcess> process_;
};

}  // namespace marvin::test_support
