#include "support/signed_package.h"

#include "store/package.h"
#include "store/util.h"

namespace marvin::test_support {

std::filesystem::path pack_signed(const std::filesystem::path& skill_dir,
                                  const std::filesystem::path& out_dir,
                                  const store::SecretKey& key) {
  store::PackedSkill p = store::pack_skill(skill_dir, &key);
  std::filesystem::create_directories(out_dir);
  std::filesystem::path file = out_dir / p.file_name();
  store::write_file_atomic(file, p.archive);
  store::write_file_atomic(store::signature_path_for(file), *p.signature);
  return file;
}

}  // namespace marvin::test_support
