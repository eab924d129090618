// The real `marvin` binary, as a carer would use it: keys made with the real `minisign`
// tool (one of them password-protected), `marvin skill pack --sign`, `index`, `install`,
// `list`, `upgrade`, `rollback`, `remove`, while a `marvin run --sim` process (stdin piped)
// picks each change up without a restart: it answers a Lua skill's sentence only once
// `install` ran in another process, the new version's after an upgrade, the old one again
// after an upgrade that fails to load (automatic rollback, in the lock file too), and no
// longer after `remove`. Then the permission prompt on a real terminal (a pty): "n" refuses
// and leaves the skills directory byte-identical, "y" installs.
//
// Synchronisation is on output lines only (a generous timeout, never a sleep). Every process
// gets its own $HOME and $MARVIN_SKILLS_DIR under a temporary folder.
#include <doctest/doctest.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/child_process.h"
#include "test_skills.h"

namespace {

using marvin::app::test::TempDir;
using marvin::test_support::ChildOptions;
using marvin::test_support::ChildProcess;
using marvin::test_support::exit_code;
namespace fs = std::filesystem;
namespace test = marvin::app::test;

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct Output {
  int exit_code = -1;
  std::string text;    // stdout
  std::string errors;  // stderr (the log, and "marvin: <error>")
  std::string all() const { return text + errors; }
};

// Runs a shell command line with `input` on its stdin and collects its output.
Output shell(const std::string& command, const std::string& input = "") {
  ChildProcess child = ChildProcess::shell(command);
  child.write(input);
  Output out;
  out.exit_code = exit_code(child.finish());
  out.text = child.output();
  out.errors = child.errors();
  return out;
}

// A temporary home for one test: keys, skill sources, packages, skills directory.
struct World {
  TempDir tmp;
  fs::path skills = tmp / "skills";
  fs::path key = tmp / "keys" / "marvin.key";
  fs::path pub = tmp / "keys" / "marvin.pub";

  World() {
    fs::create_directories(tmp / "keys");
    fs::create_directories(tmp / "home");
    REQUIRE_MESSAGE(shell("minisign -v").exit_code == 0,
                    "the minisign tool is needed (deps/debian-packages.txt)");
    REQUIRE(shell("minisign -G -W -p " + quote(pub) + " -s " + quote(key)).exit_code == 0);
  }
  std::string env() const {
    return "HOME=" + quote((tmp / "home").string()) +
           " MARVIN_SKILLS_DIR=" + quote((tmp / "default-skills").string()) +
           " MARVIN_DATA_DIR=" + quote((tmp / "data").string()) + " ";
  }
  Output marvin(const std::string& args, const std::string& more_env = "") const {
    return shell(env() + more_env + " " + quote(MARVIN_EXE) + " " + args);
  }
  // `marvin skill pack SRC --sign KEY -o OUT` for a Lua skill made by lua_skill().
  fs::path pack(const fs::path& src, const fs::path& out_dir) const {
    fs::create_directories(out_dir);
    std::string name = src.filename().string();
    name = name.substr(0, name.size() - 4) + ".mskill";  // <id>-<version>-src
    fs::path out = out_dir / name;
    Output o = marvin("skill pack " + quote(src) + " --sign " + quote(key) + " -o " + quote(out));
    INFO(o.all());
    REQUIRE(o.exit_code == 0);
    REQUIRE(o.text.find("(signed)") != std::string::npos);
    return out;
  }
  std::string lock_version(const std::string& id) const {
    auto lock = nlohmann::json::parse(test::read_text(skills / "skills.lock"));
    return lock["skills"][id]["version"].get<std::string>();
  }
};

bool is_no_match(const std::string& line) {
  return line.starts_with("Marvin: Sorry, I don't know how to help with that");
}

}  // namespace

TEST_CASE("a running host follows install, upgrade, failed upgrade, rollback and remove") {
  World w;
  fs::create_directories(w.skills);
  fs::path v1 = w.pack(test::lua_skill(w.tmp / "src", "hello", "1.0.0", "Hello from one"),
                       w.tmp / "packages");
  fs::path v2 =
      w.pack(test::lua_skill(w.tmp / "src", "hello", "1.1.0", "Hello from two"), w.tmp / "repo");
  fs::path broken =
      w.pack(test::lua_skill(w.tmp / "src", "hello", "1.2.0", "", "error(\"broken on purpose\")\n"),
             w.tmp / "packages");
  const std::string dir = " --skills-dir " + quote(w.skills);
  const std::string key = " --key " + quote(w.pub);

  ChildOptions host_options;
  host_options.environment = {"HOME=" + (w.tmp / "home").string(), "PATH=/usr/bin:/bin"};
  host_options.clean_environment = true;
  host_options.err_file = w.tmp / "host-stderr.txt";
  ChildProcess host({MARVIN_EXE, "run", "--sim", "--in-memory", "--no-builtin-skills",
                     "--time-zone", "UTC", "--skills-dir", w.skills.string()},
                    host_options);
  host.wait_for_line("Marvin: Hello, I'm Marvin.");
  host.send_line("hello greet");
  host.wait_for_line("You: hello greet");
  host.wait_for_line("no-match answer", is_no_match);

  // install, in another process.
  Output o = w.marvin("skill install " + quote(v1) + key + " --yes" + dir);
  INFO(o.all());
  REQUIRE(o.exit_code == 0);
  CHECK(o.text == "installed hello 1.0.0\n");
  host.wait_for_line("[skill hello 1.0.0 loaded]");
  host.send_line("hello greet");
  host.wait_for_line("Marvin: Hello from one");

  o = w.marvin("skill list" + dir);
  CHECK(o.exit_code == 0);
  CHECK(o.text.starts_with("hello 1.0.0 [lua]"));

  // upgrade from a signed repository.
  o = w.marvin("skill index " + quote(w.tmp / "repo") + " --sign " + quote(w.key));
  REQUIRE(o.exit_code == 0);
  o = w.marvin("skill upgrade --repo " + quote(w.tmp / "repo") + key + " --yes" + dir);
  INFO(o.all());
  REQUIRE(o.exit_code == 0);
  CHECK(o.text == "upgraded hello 1.1.0 (was 1.0.0)\n");
  host.wait_for_line("[skill hello 1.1.0 loaded (was 1.0.0)]");
  host.send_line("hello greet");
  host.wait_for_line("Marvin: Hello from two");

  // rollback (and back again: a second rollback undoes the first).
  o = w.marvin("skill rollback hello" + dir);
  CHECK(o.text == "rolled back hello to 1.0.0\n");
  host.wait_for_line("[skill hello 1.0.0 loaded (was 1.1.0)]");
  host.send_line("hello greet");
  host.wait_for_line("Marvin: Hello from one");
  o = w.marvin("skill rollback hello" + dir);
  CHECK(o.text == "rolled back hello to 1.1.0\n");
  host.wait_for_line("[skill hello 1.1.0 loaded (was 1.0.0)]");

  // An upgrade whose code fails to load: the host rolls it back by itself.
  o = w.marvin("skill install " + quote(broken) + key + " --yes" + dir);
  INFO(o.all());
  REQUIRE(o.exit_code == 0);
  CHECK(o.text == "upgraded hello 1.2.0 (was 1.1.0)\n");
  std::string failed = host.wait_for_line_containing("[skill hello 1.2.0 failed to load (");
  CHECK(failed.find("broken on purpose") != std::string::npos);
  CHECK(failed.ends_with("); rolled back to 1.1.0]"));
  host.wait_for_line("[skill hello 1.1.0 loaded]");
  CHECK(w.lock_version("hello") == "1.1.0");
  o = w.marvin("skill list" + dir);
  CHECK(o.text.starts_with("hello 1.1.0 [lua] (previous 1.2.0)"));
  host.send_line("hello greet");
  host.wait_for_line("Marvin: Hello from two");

  // remove.
  o = w.marvin("skill remove hello" + dir);
  CHECK(o.text == "removed hello\n");
  host.wait_for_line("[skill hello 1.1.0 unloaded]");
  host.send_line("hello greet");
  host.wait_for_line("You: hello greet");
  host.wait_for_line("no-match answer", is_no_match);

  // `marvin skills reload` asks the running host; a plain folder edited by hand is then
  // picked up (plain folders are not watched file by file).
  // (Made elsewhere and moved in, so the host never sees a half-written folder.)
  fs::path plain = test::lua_skill(w.tmp / "src", "plain", "1.0.0", "Plain here");
  fs::rename(plain, w.skills / "plain");
  host.wait_for_line("[skill plain 1.0.0 loaded]");  // a new folder in the directory is seen
  host.send_line("plain greet");
  host.wait_for_line("Marvin: Plain here");
  fs::path main_lua = w.skills / "plain" / "main.lua";
  test::write_text(main_lua, "marvin.on(\"greet\", function() marvin.say(\"Plain edited\") end)\n");
  fs::last_write_time(main_lua, fs::last_write_time(main_lua) + std::chrono::hours(1));
  o = w.marvin("skills reload" + dir);
  CHECK(o.exit_code == 0);
  CHECK(o.text.starts_with("asked running hosts to reload the skills in "));
  host.wait_for_line("[skill plain 1.0.0 loaded (was 1.0.0)]");
  host.send_line("plain greet");
  host.wait_for_line("Marvin: Plain edited");

  CHECK(exit_code(host.finish()) == 0);
  CHECK(test::read_text(w.tmp / "host-stderr.txt").find("broken on purpose") != std::string::npos);
}

TEST_CASE("install refuses what the host would not load, naming the field; nothing changes") {
  World w;
  fs::path good = w.pack(test::lua_skill(w.tmp / "src", "hello", "1.0.0", "Hi"), w.tmp / "p");
  REQUIRE(w.marvin("skill install " + quote(good) + " --key " + quote(w.pub) + " --yes" +
                   " --skills-dir " + quote(w.skills))
              .exit_code == 0);
  const auto before = test::snapshot(w.skills);
  fs::path bad =
      w.pack(test::lua_skill(w.tmp / "bad", "hello", "1.1.0", "Hi", "", "\"^1.0\""), w.tmp / "p");
  Output o = w.marvin("skill install " + quote(bad) + " --key " + quote(w.pub) + " --yes" +
                      " --skills-dir " + quote(w.skills));
  CHECK(o.exit_code != 0);
  CHECK(o.errors.find("the host would not load it: skill.json: $.host_api: ") != std::string::npos);
  CHECK(test::snapshot(w.skills) == before);
}

TEST_CASE("without --skills-dir the installed skills ($MARVIN_SKILLS_DIR) are loaded, if any") {
  World w;
  fs::path good = w.pack(test::lua_skill(w.tmp / "src", "hello", "1.0.0", "Hi"), w.tmp / "p");
  const std::string installed = "MARVIN_SKILLS_DIR=" + quote(w.skills);
  REQUIRE(w.marvin("skill install " + quote(good) + " --key " + quote(w.pub) + " --yes", installed)
              .exit_code == 0);
  Output list = w.marvin("skills list --no-builtin-skills", installed);
  CHECK(list.exit_code == 0);
  CHECK(list.text.starts_with("hello 1.0.0 (lua) \"hello\" in " +
                              fs::canonical(w.skills / "hello" / "versions" / "1.0.0").string() +
                              "\n"));
  // A default directory that does not exist is no error.
  Output none = w.marvin("skills list --no-builtin-skills",
                         "MARVIN_SKILLS_DIR=" + quote(w.tmp / "nothing-installed"));
  CHECK(none.exit_code == 0);
  CHECK(none.text == "no skills loaded\n");
  // `skills reload` needs the directory.
  Output reload = w.marvin("skills reload --skills-dir " + quote(w.tmp / "nothing-installed"));
  CHECK(reload.exit_code == 1);
  CHECK(reload.errors.find("skills directory " + (w.tmp / "nothing-installed").string() +
                           " does not exist") != std::string::npos);
  CHECK_FALSE(fs::exists(w.tmp / "nothing-installed"));
}

TEST_CASE("the permission prompt on a terminal: n refuses and changes nothing, y installs") {
  World w;
  fs::path first = w.pack(test::lua_skill(w.tmp / "src", "first", "1.0.0", "First"), w.tmp / "p");
  REQUIRE(w.marvin("skill install " + quote(first) + " --key " + quote(w.pub) + " --skills-dir " +
                   quote(w.skills))
              .exit_code == 0);  // no permissions: nothing to approve
  fs::path lamp = w.pack(test::lua_skill(w.tmp / "src", "lamp", "1.0.0", "Light", "",
                                         R"({"min": "1.0"})", R"(["light"])"),
                         w.tmp / "p");
  const auto before = test::snapshot(w.skills);
  const std::string lock_before = test::read_text(w.skills / "skills.lock");

  // Runs `install` on a pseudo-terminal, answers `answer` to the prompt; returns the exit
  // code and everything shown.
  auto install_on_terminal = [&](const std::string& answer) {
    ChildOptions on_terminal;
    on_terminal.environment = {"HOME=" + (w.tmp / "home").string()};
    on_terminal.clean_environment = true;
    on_terminal.terminal = true;
    ChildProcess install({MARVIN_EXE, "skill", "install", lamp.string(), "--key", w.pub.string(),
                          "--skills-dir", w.skills.string()},
                         on_terminal);
    const bool answered = install.read_until([](const std::string& shown_so_far) {
      return shown_so_far.find("Approve? [y/N] ") != std::string::npos;
    });
    if (answered) install.write(answer + "\n");
    const int status = install.finish();
    const std::string shown = install.output();
    INFO(shown);
    CHECK(answered);
    CHECK(shown.find("lamp 1.0.0 asks for these permissions:") != std::string::npos);
    CHECK(shown.find("  - light") != std::string::npos);
    return std::make_pair(exit_code(status), shown);
  };

  CHECK(install_on_terminal("n").first != 0);
  CHECK(test::snapshot(w.skills) == before);
  CHECK(test::read_text(w.skills / "skills.lock") == lock_before);

  // Without a terminal the install is refused too, and says how to approve.
  Output piped = w.marvin("skill install " + quote(lamp) + " --key " + quote(w.pub) +
                          " --skills-dir " + quote(w.skills));
  CHECK(piped.exit_code != 0);
  CHECK(piped.all().find("not a terminal: pass --yes to approve") != std::string::npos);
  CHECK(test::snapshot(w.skills) == before);

  auto approved = install_on_terminal("y");
  INFO(approved.second);
  CHECK(approved.first == 0);
  CHECK(approved.second.find("installed lamp 1.0.0") != std::string::npos);
  CHECK(w.lock_version("lamp") == "1.0.0");
}

TEST_CASE("a password-protected minisign key signs packages with MARVIN_SIGN_PASSWORD") {
  World w;
  fs::path key = w.tmp / "keys" / "protected.key";
  fs::path pub = w.tmp / "keys" / "protected.pub";
  // minisign reads the password (twice) from standard input when it is not a terminal.
  REQUIRE(
      shell("minisign -G -p " + quote(pub) + " -s " + quote(key), "correct horse\ncorrect horse\n")
          .exit_code == 0);
  REQUIRE(test::read_text(key).find("encrypted secret key") != std::string::npos);
  fs::path src = test::lua_skill(w.tmp / "src", "hello", "1.0.0", "Hi");
  fs::path out = w.tmp / "hello-1.0.0.mskill";
  const std::string pack =
      "skill pack " + quote(src) + " --sign " + quote(key) + " -o " + quote(out);

  Output none = w.marvin(pack);
  CHECK(none.exit_code != 0);
  CHECK(none.errors.find("MARVIN_SIGN_PASSWORD") != std::string::npos);
  CHECK_FALSE(fs::exists(out));

  Output wrong = w.marvin(pack, "MARVIN_SIGN_PASSWORD=wrong");
  INFO(wrong.all());
  CHECK(wrong.exit_code != 0);
  CHECK(wrong.errors.find("wrong password for the secret key") != std::string::npos);
  CHECK_FALSE(fs::exists(out));

  Output ok = w.marvin(pack, "MARVIN_SIGN_PASSWORD='correct horse'");
  INFO(ok.all());
  REQUIRE(ok.exit_code == 0);
  CHECK(shell("minisign -V -q -p " + quote(pub) + " -m " + quote(out)).exit_code == 0);
  Output installed = w.marvin("skill install " + quote(out) + " --key " + quote(pub) +
                              " --yes --skills-dir " + quote(w.skills));
  CHECK(installed.text == "installed hello 1.0.0\n");
}
