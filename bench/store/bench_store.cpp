// Skill store figures: verifying and installing a 1 MB package, verifying an index of
// 1,000 skills. Each figure comes with a baseline measured in the same run (reading the
// bytes, hashing them, parsing the JSON without a signature check) so the ratio says what
// the store's own work costs. Never fails on time.
#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <vector>

#include "common/log.h"
#include "store/installer.h"
#include "store/package.h"
#include "store/repository.h"
#include "store/util.h"

namespace fs = std::filesystem;
using namespace marvin::store;

namespace {

// Median of `runs` timings of fn, in microseconds.
double median_us(int runs, const std::function<void(int)>& fn) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    auto a = std::chrono::steady_clock::now();
    fn(i);
    auto b = std::chrono::steady_clock::now();
    t.push_back(std::chrono::duration<double, std::micro>(b - a).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

void write(const fs::path& p, const std::string& s) {
  fs::create_directories(p.parent_path());
  write_file_atomic(p, s);
}

}  // namespace

int main() {
  marvin::set_log_level(marvin::LogLevel::kWarning);
  std::string tmpl = (fs::temp_directory_path() / "marvin-bench-store-XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) return 1;
  fs::path root = tmpl;
  SecretKey key = generate_secret_key();

  // A 1 MB Lua skill: 16 files of 64 KB of pseudo-random text (compresses like source).
  fs::path src = root / "big";
  write(src / "skill.json", R"({"id":"big","version":"1.0.0","kind":"lua","host_api":"^1.0","permissions":["speech"]})");
  std::mt19937 rng(42);
  const char* words[] = {"local ", "function ", "marvin.say(", "end\n", "return ", "if ", "then ", "x ", "= ", "1 "};
  for (int f = 0; f < 16; ++f) {
    std::string text;
    while (text.size() < 64 * 1024) text += words[rng() % 10];
    write(src / (std::string("part") + std::to_string(f) + ".lua"), text);
  }
  PackedSkill packed = pack_skill(src, &key);
  fs::path pkg = root / packed.file_name();
  write_file_atomic(pkg, packed.archive);
  write_file_atomic(signature_path_for(pkg), *packed.signature);
  std::printf("package: 1.0 MB of files -> %.1f KB .mskill\n", static_cast<double>(packed.archive.size()) / 1024.0);

  const int runs = 15;
  double read_hash = median_us(runs, [&](int) { (void)sha256_digest(read_file(pkg)); });
  double verify = median_us(runs, [&](int) {
    Bytes b = read_file(pkg);
    (void)verify_package_signature(b, read_text_file(signature_path_for(pkg)), {key.public_key()}, pkg.string());
  });
  double extract = median_us(runs, [&](int i) {
    fs::path d = root / (std::string("x") + std::to_string(i));
    fs::create_directories(d);
    extract_archive(read_file(pkg), d, ArchiveLimits{}, pkg.string(), /*durable=*/false);
    fs::remove_all(d);
  });
  auto install_once = [&](bool durable) {
    return median_us(runs, [&](int i) {
      InstallOptions o;
      o.assume_yes = true;
      o.durable = durable;
      Installer inst(root / (std::string("skills-") + std::to_string(durable) + "-" + std::to_string(i)), o);
      inst.install({pkg, {}, {key.public_key()}, std::nullopt, "bench"});
    });
  };
  double install_fast = install_once(false);
  double install_durable = install_once(true);
  std::printf("baseline read + sha256 of the package:            %8.0f us\n", read_hash);
  std::printf("verify signature (read, sha256, BLAKE2b, Ed25519): %8.0f us  (%.1fx baseline)\n", verify, verify / read_hash);
  std::printf("extract with all checks, no fsync:                 %8.0f us\n", extract);
  std::printf("verify + install (stage, check, activate), no fsync: %6.0f us  (%.1fx baseline)\n", install_fast,
              install_fast / read_hash);
  std::printf("verify + install, durable (fsync every step):      %8.0f us  (%.1fx baseline)\n", install_durable,
              install_durable / read_hash);

  // An index of 1,000 skills with 2 versions each.
  nlohmann::json skills = nlohmann::json::object();
  for (int s = 0; s < 1000; ++s) {
    std::string id = std::string("skill") + std::to_string(s);
    for (const char* v : {"1.0.0", "1.1.0"}) {
      skills[id]["versions"][v] = {{"file", id + "-" + v + ".mskill"},
                                   {"digest", sha256_digest(Bytes{static_cast<std::uint8_t>(s)})},
                                   {"size", 12345},
                                   {"kind", "lua"},
                                   {"permissions", {"speech", "storage"}},
                                   {"host_api", "^1.0"}};
    }
  }
  std::string index = nlohmann::json{{"format", "marvin-index/1"}, {"name", "bench"}, {"sequence", 1}, {"skills", skills}}.dump(2) + "\n";
  std::string sig = sign_message(Bytes(index.begin(), index.end()), key, "marvin-index bench sequence=1");
  double parse_only = median_us(runs, [&](int) { nlohmann::json j = nlohmann::json::parse(index);
    if (j.size() != 4) std::abort(); });
  double verified = median_us(runs, [&](int) { (void)verify_index(index, sig, {key.public_key()}, "index.json"); });
  std::printf("index: 1000 skills x 2 versions, %.0f KB\n", static_cast<double>(index.size()) / 1024.0);
  std::printf("baseline nlohmann::json::parse only:               %8.0f us\n", parse_only);
  std::printf("verify + parse + check index:                      %8.0f us  (%.1fx baseline)\n", verified, verified / parse_only);
  fs::remove_all(root);
  return 0;
}
