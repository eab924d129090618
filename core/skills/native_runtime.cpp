#include "skills/native_runtime.h"

#include <dlfcn.h>

#include <cstddef>
#include <stdexcept>
#include <vector>

namespace marvin::skills {
namespace {

std::string version(unsigned major, unsigned minor) {
  return std::to_string(major) + "." + std::to_string(minor);
}

// Calls a skill function that writes text into a caller-owned buffer, growing it once
// if the skill reports MARVIN_ERR_TRUNCATED.
std::string text_of(const marvin_text_out& out) {
  return std::string(out.data, out.length < out.capacity ? out.length : out.capacity - 1);
}

class NativeInstance : public SkillInstance {
 public:
  NativeInstance(const marvin_skill_descriptor* descriptor, void* instance,
                 std::shared_ptr<void> library)
      : descriptor_(descriptor), instance_(instance), library_(std::move(library)) {}

  ~NativeInstance() override { descriptor_->destroy(instance_); }

  marvin_status handle(const marvin_request& request, std::string* error) override {
    error_buffer_.assign(1024, '\0');
    marvin_text_out out{error_buffer_.data(), error_buffer_.size(), 0};
    marvin_status status = descriptor_->handle(instance_, &request, &out);
    if (status != MARVIN_OK && error) {
      *error = out.length > 0 ? text_of(out) : std::string("the skill gave no reason");
    }
    return status;
  }

 private:
  const marvin_skill_descriptor* descriptor_;
  void* instance_;
  std::shared_ptr<void> library_;   // released after destroy(): the library outlives its instance
  std::vector<char> error_buffer_;  // reused: no allocation per request in steady state
};

}  // namespace

void check_descriptor(const marvin_skill_descriptor* d, const Manifest& manifest,
                      const std::string& where) {
  std::string who = "skill '" + manifest.id + "' (" + where + ")";
  if (!d) throw std::runtime_error(who + ": " MARVIN_SKILL_DESCRIPTOR_SYMBOL "() returned NULL");
  if (d->abi_major != MARVIN_ABI_MAJOR) {
    throw std::runtime_error(
        who + " was built for Marvin ABI " + version(d->abi_major, d->abi_minor) +
        " but this host speaks ABI " + version(MARVIN_ABI_MAJOR, MARVIN_ABI_MINOR) +
        ": the major versions must be equal; rebuild the skill with a matching SDK");
  }
  if (d->abi_minor > MARVIN_ABI_MINOR) {
    throw std::runtime_error(who + " was built for Marvin ABI " +
                             version(d->abi_major, d->abi_minor) + ", newer than this host's ABI " +
                             version(MARVIN_ABI_MAJOR, MARVIN_ABI_MINOR) +
                             ": update Marvin or rebuild the skill with an older SDK");
  }
  if (d->struct_size < offsetof(marvin_skill_descriptor, handle) + sizeof(d->handle)) {
    throw std::runtime_error(who + ": descriptor is " + std::to_string(d->struct_size) +
                             " bytes, too small for ABI " + version(d->abi_major, d->abi_minor));
  }
  if (!d->skill_id || manifest.id != d->skill_id) {
    throw std::runtime_error(who + ": the library says it is skill '" +
                             std::string(d->skill_id ? d->skill_id : "(null)") +
                             "' but skill.json says '" + manifest.id + "'");
  }
  if (!d->create || !d->destroy || !d->handle) {
    throw std::runtime_error(who + ": descriptor lacks create, destroy or handle");
  }
}

std::unique_ptr<SkillInstance> make_native_instance(const marvin_skill_descriptor* descriptor,
                                                    const Manifest& manifest,
                                                    const marvin_robot_api* api, marvin_host* host,
                                                    std::shared_ptr<void> keep_alive,
                                                    const std::string& where) {
  check_descriptor(descriptor, manifest, where);
  std::vector<char> error(1024, '\0');
  marvin_text_out out{error.data(), error.size(), 0};
  void* instance = descriptor->create(api, host, &out);
  if (!instance) {
    throw std::runtime_error("skill '" + manifest.id + "' (" + where + ") failed to start: " +
                             (out.length ? text_of(out) : std::string("no reason given")));
  }
  return std::make_unique<NativeInstance>(descriptor, instance, std::move(keep_alive));
}

std::unique_ptr<SkillInstance> NativeRuntime::load(const Manifest& manifest,
                                                   const std::filesystem::path& dir,
                                                   const marvin_robot_api* api, marvin_host* host) {
  std::filesystem::path library = dir / manifest.entry;
  if (!std::filesystem::is_regular_file(library)) {
    throw std::runtime_error("skill '" + manifest.id + "': library " + library.string() +
                             " does not exist (\"entry\" in skill.json)");
  }
  dlerror();
  void* handle = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw std::runtime_error("skill '" + manifest.id + "': cannot load " + library.string() + ": " +
                             (why ? why : "unknown error"));
  }
  std::shared_ptr<void> keep(handle, [](void* h) { dlclose(h); });
  void* symbol = dlsym(handle, MARVIN_SKILL_DESCRIPTOR_SYMBOL);
  if (!symbol) {
    throw std::runtime_error("skill '" + manifest.id + "': " + library.string() +
                             " does not export " MARVIN_SKILL_DESCRIPTOR_SYMBOL "()");
  }
  auto get = reinterpret_cast<marvin_skill_descriptor_fn>(symbol);
  return make_native_instance(get(), manifest, api, host, std::move(keep), library.string());
}

}  // namespace marvin::skills
