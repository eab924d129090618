// Who "call my daughter" / "phone Anna" / "ring the doctor" / "call 0123 456 789" means,
// and the sentences the phone skill says about it. Pure functions over the contacts the
// caller passes in (telephony does not read the data store itself; core/app or the skill
// hands the contacts over).
#pragma once

#include <string>
#include <vector>

namespace marvin::telephony {

struct CallTarget {
  std::string name;                  // "Anna Schmidt"
  std::string relation;              // "daughter"
  std::vector<std::string> aliases;  // "my daughter", "Annie"
  std::vector<std::string> numbers;  // phone numbers and sip: URIs, the first is dialled
};

struct Callee {
  enum class Kind {
    kContact,    // exactly one contact with a number: `target`, `number`
    kNumber,     // the user said a number: `number`
    kAmbiguous,  // several contacts match: `candidates` (ask which)
    kNoNumber,   // one contact, but nothing to dial: `target`
    kUnknown,    // nobody matches
  };
  Kind kind = Kind::kUnknown;
  CallTarget target;
  std::string number;
  std::vector<std::string> candidates;
  // What to say: the confirmation question for kContact/kNumber ("Call Anna Schmidt on
  // +49 30 1234?"), the question or the refusal otherwise.
  std::string say;
};

// `who` is the slot as heard: "my daughter", "Anna", "the doctor", "0123 456 789".
Callee resolve_callee(const std::string& who, const std::vector<CallTarget>& contacts);

}  // namespace marvin::telephony
