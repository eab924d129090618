// Loads native skills: shared libraries built with the SDK (marvin/skill.h).
//
// The loader never trusts a library before checking it: the manifest was read and
// validated first; the library is opened with RTLD_NOW | RTLD_LOCAL (every symbol
// resolved up front, none leaking into other skills); its descriptor must carry the same
// ABI major as the host and a minor that is not newer, and the skill id of its manifest.
// Only then is create() called. A library stays loaded until the last instance made from
// it is destroyed.
#pragma once

#include <memory>
#include <string>

#include "skills/skill_runtime.h"

namespace marvin::skills {

class NativeRuntime : public SkillRuntime {
 public:
  std::string kind() const override { return "native"; }
  std::unique_ptr<SkillInstance> load(const Manifest& manifest, const std::filesystem::path& dir,
                                      const marvin_robot_api* api, marvin_host* host) override;
};

// Checks a descriptor against the host's ABI and the manifest. Throws std::runtime_error
// naming `where` (the library path, or "in-process") and both versions on a mismatch.
void check_descriptor(const marvin_skill_descriptor* descriptor, const Manifest& manifest,
                      const std::string& where);

// Makes an instance from a descriptor already in the process (a skill compiled into a test
// or a benchmark). `keep_alive` is held until the instance is destroyed (the library).
std::unique_ptr<SkillInstance> make_native_instance(const marvin_skill_descriptor* descriptor,
                                                    const Manifest& manifest,
                                                    const marvin_robot_api* api, marvin_host* host,
                                                    std::shared_ptr<void> keep_alive = {},
                                                    const std::string& where = "in-process");

}  // namespace marvin::skills
