#include "marvin/testing/skill_harness.hpp"

#include <stdexcept>

#include "mock_robot_impl.h"
#include "skills/manager.h"
#include "skills/registry.h"

namespace marvin::testing {

struct SkillHarness::Impl {
  explicit Impl(std::string skill_id) : robot(std::move(skill_id)) {}

  void start() {
    MockRobot::Impl& r = *robot.impl_;
    registry = std::make_unique<skills::Registry>(r.services);
    skills::ManagerOptions options;
    options.run_long_inline = true;
    manager = std::make_unique<skills::Manager>(*registry, r, options);
    // Skills talk through the manager (so "repeat" knows their last sentence).
    r.services.user = manager.get();
  }

  void check_loaded() {
    if (!registry->errors().empty()) throw std::runtime_error(registry->errors().front().message);
    if (registry->skills().size() != 1) throw std::runtime_error("no skill was loaded");
  }

  MockRobot robot;
  std::unique_ptr<skills::Registry> registry;
  std::unique_ptr<skills::Manager> manager;
};

SkillHarness::SkillHarness(const std::filesystem::path& skill_dir) {
  skills::Manifest manifest = skills::load_manifest(skill_dir / "skill.json");
  impl_ = std::make_unique<Impl>(manifest.id);
  impl_->start();
  impl_->registry->load_skill(skill_dir);
  impl_->check_loaded();
}

SkillHarness::SkillHarness(const std::filesystem::path& manifest_file,
                           const marvin_skill_descriptor* descriptor) {
  skills::Manifest manifest = skills::load_manifest(manifest_file);
  impl_ = std::make_unique<Impl>(manifest.id);
  impl_->start();
  impl_->registry->add_native(manifest, descriptor);
  impl_->check_loaded();
}

SkillHarness::~SkillHarness() {
  // The manager and the skill go before the robot they talk to.
  impl_->manager.reset();
  impl_->registry.reset();
}

MockRobot& SkillHarness::robot() { return impl_->robot; }

std::vector<std::string> SkillHarness::say(std::string_view utterance,
                                           std::vector<std::string> answers) {
  MockRobot::Impl& r = *impl_->robot.impl_;
  for (auto& answer : answers) r.answers.push_back(std::move(answer));
  std::size_t before = r.said.size();
  impl_->manager->handle(utterance);
  return std::vector<std::string>(r.said.begin() + static_cast<std::ptrdiff_t>(before),
                                  r.said.end());
}

std::string SkillHarness::intent_of(std::string_view utterance) const {
  auto match = impl_->registry->interpreter().match(utterance, impl_->manager->context());
  return match ? match->skill_id + "/" + match->intent : std::string();
}

}  // namespace marvin::testing
