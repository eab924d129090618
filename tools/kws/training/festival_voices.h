// A third synthesiser for training data: the Festival Speech Synthesis System (Debian
// `festival` and its `festvox-*` voices, run as `text2wave`). Its diphone voices are cut from
// recordings of real speakers, its HTS voices are trained on them, and its Czech, Finnish and
// Catalan voices say "marvin" with their own language's sounds: a wider set of speakers than
// espeak-ng and flite give. Session 17 found the head trained without them missing most of
// their "marvin"s (models/README.md). Tools only; the robot never runs it.
#pragma once

#include <string>
#include <vector>

namespace marvin::perception::kws {

// The festival voices the training tools use.
const std::vector<std::string>& festival_voices();

// Four more Debian voices, installed but kept out of training on purpose: the held-out
// festival voices of models/README.md's evaluation (tools/kws/festival-heldout says the
// keyword with them).
const std::vector<std::string>& festival_heldout_voices();

// `text` said by festival `voice` (a name from festival_voices() or
// festival_heldout_voices()), 16 kHz float, silence trimmed. `stretch` lengthens the durations
// (> 1 slower) where the voice's duration model follows festival's Duration_Stretch (the
// English voices; the others ignore it). Throws std::runtime_error naming text2wave and
// `scripts/setup` when festival is missing, and naming the voice when it is unknown or says
// nothing.
std::vector<float> synthesize_festival(const std::string& text, const std::string& voice,
                                       float stretch);

}  // namespace marvin::perception::kws
