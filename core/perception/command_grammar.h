// The speech recognizer's grammar, generated from the skills' utterance templates.
//
// Templates use the hassil syntax of core/interpret: words, `(a|b)` alternatives, `[a]`
// optionals (`[a|b]`), `{slot}` slots, nested freely. Each slot becomes a JSGF rule:
//   kPhrases  -> its phrases (contacts, device names, object names: the current values)
//   kNumber   -> number words, zero to nine hundred ninety nine
//   kDuration -> "twenty minutes", "an hour and a half", "half an hour", ...
//   kDateTime -> "at eight pm", "tomorrow at nine", "in ten minutes", "every day at eight", ...
//   kText     -> one or more words of GrammarOptions::free_text_words
// and the conversation phrases (stop, yes, no, repeat, ...) are always accepted.
//
// Words are lower-cased, punctuation other than apostrophes dropped, digits spelled out
// ("8" -> "eight"). A word the recognizer's dictionary does not know cannot be recognised:
// an alternative, optional part or phrase containing one is left out and reported in
// GrammarResult::skipped; a template that needs it is left out whole.
//
// The grammar is plain data: regenerate it (and hand it to SpeechRecognizer::set_grammar)
// whenever skills are loaded or unloaded or slot values (contacts, devices) change.
#pragma once

#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::perception {

enum class SlotKind { kPhrases, kNumber, kDuration, kDateTime, kText };

struct GrammarSlot {
  std::string name;
  SlotKind kind = SlotKind::kPhrases;
  std::vector<std::string> phrases;  // kPhrases only
};

struct GrammarIntent {
  std::string name;  // for messages ("time.query")
  std::vector<std::string> templates;
  std::vector<GrammarSlot> slots;
};

struct GrammarOptions {
  // Accepted after any intent as whole utterances (the interpreter's built-in intents).
  std::vector<std::string> conversation_phrases = {
      "stop", "cancel", "never mind", "yes", "yeah", "sure", "no", "nope", "repeat",
      "say that again", "marvin stop", "stop it", "please stop",
      // how Marvin speaks (interpret/voice_change.h)
      "speak slower", "speak faster", "speak louder", "speak up", "speak more quietly",
      "i can not hear you"};
  // The words a kText slot may be made of (in addition to every template and slot word).
  std::vector<std::string> free_text_words = default_free_text_words();
  // Also accept each slot's values alone. Off by default: it loosens the grammar and costs
  // accuracy on whole commands; for the answer to a question ("Whom should I call?") build
  // a small grammar from that one slot instead (Reply::answer_grammar in voice_loop.h).
  bool accept_bare_slot_values = false;
  // Words every sentence may start with, e.g. the wake word: a detector reports the end of
  // "marvin" a little early, and the rest of it in front of the command throws the search
  // off ("marvin, tell me the time" heard as "delete reminder"); "[marvin]" absorbs it. The
  // recognised text then starts with these words when they were heard. "" = none.
  std::string optional_prefix;
  // Politeness and filler people put around a command (template syntax), accepted around
  // every intent's templates but not around the conversation phrases: "could you please
  // tell me the time", "set a timer for ten minutes please". "" = none. Words the
  // recognizer does not know are left out like any template word.
  std::string polite_before;
  std::string polite_after;

  // What the host uses: "[hey] [(could|can|would|will) you] [please]" before and
  // "[please] [(thanks|thank you)]" after.
  static std::string default_polite_before();
  static std::string default_polite_after();

  static std::vector<std::string> default_free_text_words();
};

struct GrammarResult {
  std::string jsgf;                  // "#JSGF V1.0; grammar marvin; public <command> = ..."
  std::vector<std::string> skipped;  // one line per left-out word, naming intent and template
  std::size_t templates_used = 0;
};

// A template that does not parse or names an undeclared slot; what() names intent,
// template and 1-based column.
class GrammarError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Builds the grammar. `known_word` says whether the recognizer can hear a word (pass
// SpeechRecognizer::knows_word); an empty function accepts every word. Throws GrammarError
// on a bad template, or when nothing at all is left to recognise.
GrammarResult build_command_grammar(std::span<const GrammarIntent> intents,
                                    const GrammarOptions& options = {},
                                    const std::function<bool(std::string_view)>& known_word = {});

// Lower case, apostrophes kept, other punctuation dropped, digits spelled out:
// "Call Anna, at 8!" -> {"call", "anna", "at", "eight"}.
std::vector<std::string> grammar_words(std::string_view text);

}  // namespace marvin::perception
