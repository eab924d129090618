// The home service (core/home) as the skills see it (skills::SmartHome): devices as the
// JSON of marvin/robot.h's smarthome_devices, and "set and confirm" with a sentence for
// every way it can fail. The host also routes Marvin's activity and events to the bus
// through the service (app/host.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include "home/home_service.h"
#include "skills/smart_home.h"

namespace marvin::app {

nlohmann::json device_json(const home::Device& device);

class HomeLink final : public skills::SmartHome {
 public:
  explicit HomeLink(home::HomeService& service) : service_(service) {}
  nlohmann::json devices() override;
  Reply set(const std::string& device, const nlohmann::json& state) override;
  void on_change(std::function<void()> listener) override {
    service_.on_devices_changed(std::move(listener));
  }

 private:
  home::HomeService& service_;
};

}  // namespace marvin::app
