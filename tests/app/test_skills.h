// Helpers for the app tests: Lua skill folders in the host's manifest format. Temporary
// directories, files, snapshots and signed packages are the shared ones (tests/support).
#pragma once

#include <filesystem>
#include <string>

#include "support/files.h"
#include "support/signed_package.h"

namespace marvin::app::test {

namespace fs = std::filesystem;

// TempDir, write_text, read_text, snapshot, pack_signed.
using namespace test_support;

// A Lua skill folder <parent>/<id>-<version>-src whose intent "greet" ("<id> greet" or
// `sentence`) says `answer`. `main_lua` replaces the whole main.lua when not empty.
// `host_api` is the skill.json value as JSON text.
fs::path lua_skill(const fs::path& parent, const std::string& id, const std::string& version,
                   const std::string& answer, const std::string& main_lua = "",
                   const std::string& host_api = R"({"min": "1.0"})",
                   const std::string& permissions = "[]");

}  // namespace marvin::app::test
