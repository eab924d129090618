// The sonar. See sonar_scanner.h.
#include "devices/sonar_scanner.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace marvin::devices {

MedianFilter::MedianFilter(std::size_t window)
    : ring_(std::max<std::size_t>(window, 1)), scratch_(ring_.size()) {}

int MedianFilter::add(int value) {
  ring_[next_] = value;
  next_ = (next_ + 1) % ring_.size();
  count_ = std::min(count_ + 1, ring_.size());
  return median();
}

int MedianFilter::median() const {
  if (count_ == 0) return 0;
  std::copy_n(ring_.begin(), count_, scratch_.begin());
  auto mid = scratch_.begin() + static_cast<std::ptrdiff_t>((count_ - 1) / 2);
  std::nth_element(scratch_.begin(), mid, scratch_.begin() + static_cast<std::ptrdiff_t>(count_));
  return *mid;
}

SonarScanner::SonarScanner(SerialLink& link, std::size_t median_window,
                           std::chrono::milliseconds max_age)
    : link_(link), window_(median_window), max_age_(max_age) {
  callback_ = link_.add_telemetry_callback([this](const Telemetry& t) {
    if (auto* r = std::get_if<SonarReading>(&t)) add(*r);
  });
}

SonarScanner::~SonarScanner() { link_.remove_callback(callback_); }

void SonarScanner::sweep(const SweepSettings& s) {
  auto check = [](bool ok, const char* field, const std::string& expected) {
    if (!ok)
      throw std::invalid_argument(std::string("sonar sweep: ") + field + " must be " + expected);
  };
  check(s.from_deg >= 0 && s.from_deg <= 120, "from_deg", "0..120");
  check(s.to_deg >= s.from_deg && s.to_deg <= 120, "to_deg", "from_deg..120");
  check(s.step_deg >= 1 && s.step_deg <= 60, "step_deg", "1..60");
  {
    std::lock_guard lock(mu_);
    settings_ = s;
  }
  resend();
}

void SonarScanner::resend() {
  std::lock_guard lock(mu_);
  link_.send_ext(MV_SONAR_SWEEP, {MV_SWEEP_ON, static_cast<std::uint8_t>(settings_.from_deg),
                                  static_cast<std::uint8_t>(settings_.to_deg),
                                  static_cast<std::uint8_t>(settings_.step_deg)});
}

void SonarScanner::add(const SonarReading& r) {
  std::lock_guard lock(mu_);
  auto it = tracks_.find(r.angle_deg);
  if (it == tracks_.end()) it = tracks_.emplace(r.angle_deg, Track{MedianFilter(window_), 0}).first;
  it->second.filter.add(r.distance_mm);
  it->second.time_ms = r.host_time_ms;
}

void SonarScanner::forget_readings() {
  std::lock_guard lock(mu_);
  tracks_.clear();
}

std::vector<ScanPoint> SonarScanner::latest_scan() const { return latest_scan(steady_ms()); }

std::vector<ScanPoint> SonarScanner::latest_scan(std::int64_t now_ms) const {
  std::lock_guard lock(mu_);
  std::vector<ScanPoint> points;
  for (const auto& [angle, track] : tracks_) {
    if (now_ms - track.time_ms > max_age_.count()) continue;
    points.push_back({static_cast<double>(angle), track.filter.median() / 1000.0, track.time_ms});
  }
  return points;
}

}  // namespace marvin::devices
