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

// The festival voices the training tools use. Four more Debian voices (ked_diphone,
// czech_krb, czech_ph, hy_fi_mv_diphone) are installed but kept out of training on purpose:
// they are the held-out festival voices of models/README.md's evaluation.
const std::vector<std::string>& festival_voices();

// `text` said by festival `voice` (a name from festival_voices(), or one of the held-out
// voices), 16 kHz float, silence trimmed. `stretch` lengthens the durations (> 1 slower) where
// the voice's duration model follows festival's Duration_Stretch (the English voices; the
// others ignore it). Throws std::runtime_error naming text2wave and `scripts/setup` when
// festival is missing, and naming the voice when it is unknown or says nothing.
std::vector<float> synthesize_festival(const std::string& text, const std::string& voice,
                                       float stretch);

}  // namespace marvin::perception::kws
