// `marvin contacts edit`: the phone's fields (numbers, SIP addresses, relation, nicknames,
// emergency order) changed from the command line; bad input names the field and changes
// nothing that is stored.
#include <doctest/doctest.h>

#include <cstdlib>

#include "support/child_process.h"
#include "support/files.h"

namespace marvin::telephony {
namespace {

using test_support::ChildProcess;

struct Result {
  int code;
  std::string out, err;
};

Result marvin(const test_support::TempDir& data, std::vector<std::string> args) {
  const char* build = std::getenv("MARVIN_BUILD_DIR");
  std::vector<std::string> argv{std::string(build ? build : ".") + "/core/app/marvin"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--data-dir", data.path().string()});
  test_support::ChildOptions o;
  o.in = test_support::ChildStream::kNull;
  ChildProcess p(argv, o);
  const int status = p.finish();
  return {test_support::exit_code(status), p.output(), p.errors()};
}

TEST_CASE("marvin contacts edit: numbers, SIP, relation, nicknames and emergency order") {
  test_support::TempDir data;
  REQUIRE(marvin(data, {"contacts", "add", "Anna Schmidt", "--phone", "0301 1"}).out ==
          "added contact 1 Anna Schmidt\n");
  const Result edit = marvin(data, {"contacts", "edit", "1", "--sip", "sip:anna@example.org",
                                    "--relation", "daughter", "--alias", "Annie", "--alias",
                                    "my girl", "--emergency", "1", "--phone", "+49 30 2"});
  CHECK(edit.code == 0);
  CHECK(edit.out == "changed contact 1 Anna Schmidt\n");
  CHECK(marvin(data, {"contacts", "list"}).out ==
        "1  Anna Schmidt (daughter)  +49 30 2  sip:anna@example.org  aka Annie, my girl  "
        "emergency #1\n");
  // Only what is given changes; --clear-* and --emergency 0 remove.
  CHECK(marvin(data, {"contacts", "edit", "1", "--clear-phone", "--clear-alias", "--emergency",
                      "0", "--name", "Anna Berg"})
            .code == 0);
  CHECK(marvin(data, {"contacts", "list"}).out ==
        "1  Anna Berg (daughter)  sip:anna@example.org\n");
}

TEST_CASE("marvin contacts edit: bad input names the field and nothing changes") {
  test_support::TempDir data;
  REQUIRE(marvin(data, {"contacts", "add", "Tom", "--phone", "0301 1", "--relation", "son"})
              .code == 0);
  const std::string before = marvin(data, {"contacts", "list"}).out;
  Result r = marvin(data, {"contacts", "edit", "1", "--sip", "anna@example.org", "--relation",
                           "brother"});
  CHECK(r.code == 2);
  CHECK(r.err.find("contacts edit 1: sip_uris: 'anna@example.org' is not a SIP address "
                   "(expected sip:user@host); nothing was changed") != std::string::npos);
  r = marvin(data, {"contacts", "edit", "1", "--phone", "call me", "--name", "Thomas"});
  CHECK(r.code == 2);
  CHECK(r.err.find("phone_numbers: 'call me' is not a phone number") != std::string::npos);
  r = marvin(data, {"contacts", "edit", "1", "--emergency", "-1"});
  CHECK(r.code == 2);
  CHECK(r.err.find("emergency_order: must be 0 (none) or 1, 2, ... (the order), got -1") !=
        std::string::npos);
  r = marvin(data, {"contacts", "edit", "1", "--name", ""});
  CHECK(r.code == 2);
  CHECK(r.err.find("name: a contact needs a name") != std::string::npos);
  r = marvin(data, {"contacts", "edit", "7", "--relation", "son"});
  CHECK(r.code == 1);
  CHECK(r.err.find("no contact with id 7") != std::string::npos);
  CHECK(marvin(data, {"contacts", "list"}).out == before);
}

}  // namespace
}  // namespace marvin::telephony
