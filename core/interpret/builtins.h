// The conversation intents every utterance is checked against: stop, yes, no, repeat.
#pragma once

#include <string_view>

#include "interpret/interpreter.h"

namespace marvin::interpret {

// Phrases (after normalisation, and after dropping a leading "marvin" / "hey marvin" /
// "ok marvin" and a leading or trailing "please"):
//   stop:   stop, cancel, never mind, nevermind, stop it, stop that, cancel that, abort,
//           halt, quiet, be quiet, shut up, enough, that's enough, forget it, stop stop
//   yes:    yes, yeah, yep, yup, sure, ok, okay, of course, yes please, correct, right,
//           do it, go ahead, absolutely, affirmative, that's right, please do
//   no:     no, nope, nah, no thanks, no thank you, don't, do not, negative, not now
//   repeat: repeat, repeat that, say that again, say it again, again, pardon,
//           what did you say, come again, sorry what
Builtin classify_builtin(std::string_view utterance);

}  // namespace marvin::interpret
