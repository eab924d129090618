#include "scripting/lua_runtime.h"

#include <algorithm>
#include <stdexcept>

#include "common/log.h"

namespace marvin::scripting {

void LuaSkillInstance::poll(std::int64_t now_ms) {
  std::string error;
  if (skill_->run_due_timers(now_ms, &error) != MARVIN_OK) {
    log(LogLevel::kWarning, "lua", "skill '" + skill_->spec().id + "': timer: " + error);
  }
}

SkillSpec LuaRuntime::spec_of(const skills::Manifest& manifest, const std::filesystem::path& dir) {
  SkillSpec spec;
  spec.id = manifest.id;
  spec.folder = dir;
  spec.entry = manifest.entry.empty() ? "main.lua" : manifest.entry;
  for (const auto& intent : manifest.intents) spec.intents.push_back(intent.name);
  spec.permissions = manifest.permissions;
  return spec;
}

Limits LuaRuntime::limits_for(const skills::Manifest& manifest) const {
  Limits limits = limits_;
  const auto lua = manifest.raw.find("lua");
  if (lua == manifest.raw.end() || !lua->is_object()) return limits;
  const auto lower = [&](const char* field, auto apply) {
    const auto value = lua->find(field);
    if (value == lua->end()) return;
    if (!value->is_number_unsigned() && !value->is_number_integer()) {
      throw std::runtime_error(manifest.file.string() + ": $.lua." + field +
                               ": expected a positive integer");
    }
    const auto number = value->get<std::int64_t>();
    if (number <= 0) {
      throw std::runtime_error(manifest.file.string() + ": $.lua." + field +
                               ": expected a positive integer");
    }
    apply(static_cast<std::uint64_t>(number));
  };
  lower("memory_kb", [&](std::uint64_t kb) {
    limits.memory_bytes = std::min<std::size_t>(limits.memory_bytes, static_cast<std::size_t>(kb) * 1024);
  });
  lower("instructions", [&](std::uint64_t n) { limits.instructions = std::min(limits.instructions, n); });
  lower("time_ms", [&](std::uint64_t ms) {
    limits.wall_time = std::min(limits.wall_time, std::chrono::milliseconds(static_cast<std::int64_t>(ms)));
  });
  return limits;
}

std::unique_ptr<skills::SkillInstance> LuaRuntime::load(const skills::Manifest& manifest,
                                                        const std::filesystem::path& dir,
                                                        const marvin_robot_api* api,
                                                        marvin_host* host) {
  auto skill = std::make_unique<LuaSkill>(spec_of(manifest, dir), api, host, limits_for(manifest),
                                          clock_);
  return std::make_unique<LuaSkillInstance>(std::move(skill));
}

}  // namespace marvin::scripting
