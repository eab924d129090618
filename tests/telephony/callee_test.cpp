#include "telephony/callee.h"

#include <doctest/doctest.h>

namespace marvin::telephony {
namespace {

const std::vector<CallTarget> kContacts = {
    {"Anna Schmidt", "daughter", {"Annie"}, {"+49 30 1234"}},
    {"Dr Weber", "doctor", {}, {"sip:weber@example.org"}},
    {"Anna Berg", "neighbour", {}, {"0171 555"}},
    {"Tom", "son", {}, {}},
};

TEST_CASE("call my daughter / ring the doctor / phone Annie: one contact, confirmed with the number") {
  Callee c = resolve_callee("my daughter", kContacts);
  CHECK(c.kind == Callee::Kind::kContact);
  CHECK(c.target.name == "Anna Schmidt");
  CHECK(c.say == "Call Anna Schmidt on +49 30 1234?");
  c = resolve_callee("the Doctor", kContacts);
  CHECK(c.kind == Callee::Kind::kContact);
  CHECK(c.number == "sip:weber@example.org");
  CHECK(resolve_callee("Annie", kContacts).target.name == "Anna Schmidt");
  CHECK(resolve_callee("anna berg", kContacts).number == "0171 555");
}

TEST_CASE("two Annas: the question names both") {
  const Callee c = resolve_callee("Anna", kContacts);
  CHECK(c.kind == Callee::Kind::kAmbiguous);
  CHECK(c.candidates == std::vector<std::string>{"Anna Schmidt", "Anna Berg"});
  CHECK(c.say == "Do you mean Anna Schmidt or Anna Berg?");
}

TEST_CASE("a number is called as said") {
  const Callee c = resolve_callee("0123 456 789", kContacts);
  CHECK(c.kind == Callee::Kind::kNumber);
  CHECK(c.say == "Call 0123 456 789?");
}

TEST_CASE("bad input: unknown contact, no number, nothing said") {
  Callee c = resolve_callee("the plumber", kContacts);
  CHECK(c.kind == Callee::Kind::kUnknown);
  CHECK(c.say == "I don't know anyone called the plumber.");
  c = resolve_callee("my son", kContacts);
  CHECK(c.kind == Callee::Kind::kNoNumber);
  CHECK(c.say == "I have no number for Tom.");
  c = resolve_callee("  ", kContacts);
  CHECK(c.kind == Callee::Kind::kUnknown);
  CHECK(c.say == "Whom should I call?");
  CHECK(resolve_callee("12", kContacts).kind == Callee::Kind::kUnknown);  // too short
}

}  // namespace
}  // namespace marvin::telephony
