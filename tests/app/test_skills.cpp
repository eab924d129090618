#include "test_skills.h"

namespace marvin::app::test {

fs::path lua_skill(const fs::path& parent, const std::string& id, const std::string& version,
                   const std::string& answer, const std::string& main_lua,
                   const std::string& host_api, const std::string& permissions) {
  fs::path dir = parent / (id + "-" + version + "-src");
  write_text(
      dir / "skill.json",
      "{\"id\": \"" + id + "\", \"name\": \"" + id + "\", \"version\": \"" + version +
          "\", \"kind\": \"lua\", \"host_api\": " + host_api + ", \"permissions\": " + permissions +
          ", \"intents\": [{\"name\": \"greet\", \"templates\": [\"" + id + " greet\"]}]}\n");
  write_text(dir / "main.lua", main_lua.empty() ? "marvin.on(\"greet\", function() marvin.say(\"" +
                                                      answer + "\") end)\n"
                                                : main_lua);
  return dir;
}

}  // namespace marvin::app::test
