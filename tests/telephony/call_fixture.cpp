#include "telephony/call_fixture.h"

#include <poll.h>
#include <sys/inotify.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include "telephony/baresip_config.h"

namespace marvin::telephony::testing {
namespace {

void put16(std::ofstream& out, std::uint16_t v) { out.write(reinterpret_cast<const char*>(&v), 2); }
void put32(std::ofstream& out, std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); }

PhoneSettings settings_for(const std::string& user, int port, const std::filesystem::path& dir) {
  PhoneSettings s;
  s.account_uri = "sip:" + user + "@127.0.0.1:" + std::to_string(port);
  s.sip_port = port;
  s.record_dir = dir / "recordings";
  return s;
}

}  // namespace

void write_tone_wav(const std::filesystem::path& path, double frequency_hz, double seconds) {
  const int rate = 8000;
  const auto count = static_cast<std::uint32_t>(seconds * rate);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write("RIFF", 4);
  put32(out, 36 + count * 2);
  out.write("WAVEfmt ", 8);
  put32(out, 16);
  put16(out, 1);
  put16(out, 1);
  put32(out, rate);
  put32(out, rate * 2);
  put16(out, 2);
  put16(out, 16);
  out.write("data", 4);
  put32(out, count * 2);
  for (std::uint32_t i = 0; i < count; ++i) {
    const double v = 8000.0 * std::sin(2 * std::numbers::pi * frequency_hz * i / rate);
    put16(out, static_cast<std::uint16_t>(static_cast<std::int16_t>(v)));
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::vector<double> read_wav(const std::filesystem::path& path, int* rate) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 44 || bytes.compare(0, 4, "RIFF") != 0 || bytes.compare(8, 4, "WAVE") != 0) {
    throw std::runtime_error(path.string() + ": not a WAV file (" + std::to_string(bytes.size()) +
                             " bytes)");
  }
  std::size_t pos = 12;
  std::vector<double> samples;
  while (pos + 8 <= bytes.size()) {
    std::uint32_t size = 0;
    std::memcpy(&size, bytes.data() + pos + 4, 4);
    const std::string id = bytes.substr(pos, 4);
    if (id == "fmt ") {
      std::uint32_t r = 0;
      std::memcpy(&r, bytes.data() + pos + 12, 4);
      *rate = static_cast<int>(r);
    } else if (id == "data") {
      const std::size_t end = std::min<std::size_t>(bytes.size(), pos + 8 + size);
      for (std::size_t i = pos + 8; i + 1 < end; i += 2) {
        std::int16_t v = 0;
        std::memcpy(&v, bytes.data() + i, 2);
        samples.push_back(v);
      }
      return samples;
    }
    pos += 8 + size + (size & 1);
  }
  throw std::runtime_error(path.string() + ": WAV file without a data chunk");
}

double dominant_frequency(const std::vector<double>& samples, int rate) {
  double best = 0, best_power = -1;
  for (double f = 100; f <= 3500; f += 20) {
    const double w = 2 * std::numbers::pi * f / rate;
    const double c = 2 * std::cos(w);
    double s1 = 0, s2 = 0;
    for (double x : samples) {
      const double s0 = x + c * s1 - s2;
      s2 = s1;
      s1 = s0;
    }
    const double power = s1 * s1 + s2 * s2 - c * s1 * s2;
    if (power > best_power) {
      best_power = power;
      best = f;
    }
  }
  return best;
}

ClosedFileWatch::ClosedFileWatch(const std::filesystem::path& dir) : dir_(dir) {
  fd_ = inotify_init1(IN_CLOEXEC | IN_NONBLOCK);
  if (fd_ < 0) throw std::runtime_error("inotify_init1 failed");
  std::filesystem::create_directories(dir);
  if (inotify_add_watch(fd_, dir.c_str(), IN_CLOSE_WRITE) < 0) {
    throw std::runtime_error("cannot watch " + dir.string());
  }
}

ClosedFileWatch::~ClosedFileWatch() { ::close(fd_); }

std::optional<std::filesystem::path> ClosedFileWatch::wait(const std::string& suffix,
                                                           std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) return std::nullopt;
    alignas(inotify_event) char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    for (ssize_t i = 0; i < n;) {
      const auto* event = reinterpret_cast<const inotify_event*>(buffer + i);
      const std::string name = event->len ? event->name : "";
      if (name.size() >= suffix.size() &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        return dir_ / name;
      }
      i += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
    }
  }
}

TestPeer::TestPeer(const std::filesystem::path& dir, bool auto_answer, std::string user)
    : user_(std::move(user)),
      record_dir_(dir / "recordings"),
      ua_(
          [&] {
            // Port 0: baresip's supervisor chooses it, and chooses again when another
            // program takes it first (a port chosen here could be taken before the start).
            PhoneSettings s = settings_for(user_, 0, dir);
            s.account_uri = "sip:" + user_ + "@127.0.0.1";
            s.auto_answer = auto_answer;
            return s;
          }(),
          dir / "baresip", [this](const BaresipEvent& e) { events_.add(e); }) {
  ua_.start();
  if (!ua_.wait_ready(kWait)) throw std::runtime_error("the test peer's baresip did not start");
}

std::string TestPeer::uri() const {
  return "sip:" + user_ + "@127.0.0.1:" + std::to_string(ua_.sip_port());
}

PhoneSettings marvin_settings(const std::filesystem::path& dir,
                              const std::filesystem::path& audio_in) {
  PhoneSettings s = settings_for("marvin", pick_free_port(true), dir);
  s.audio_in = audio_in;
  return s;
}

}  // namespace marvin::telephony::testing
