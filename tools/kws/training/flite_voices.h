// A second synthesiser for training data: CMU Flite (Debian `flite`, run as a program), whose
// four English voices (kal16, awb, rms, slt) are recorded speakers rather than espeak-ng's
// formant model. Mixing them into the keyword's examples and the other speech keeps the head
// from learning one synthesiser's timbre as "the keyword". Tools only; the robot never runs it.
#pragma once

#include <string>
#include <vector>

namespace marvin::perception::kws {

// The voices built into Debian's flite 2.2.
const std::vector<std::string>& flite_voices();

// `text` said by flite `voice`, 16 kHz float, silence trimmed. `stretch` lengthens the
// durations (> 1 slower), `f0_hz` moves the voice's mean pitch. Throws std::runtime_error
// naming the program and `scripts/setup` when flite is missing or fails, or naming the voice
// when it is not one of flite_voices().
std::vector<float> synthesize_flite(const std::string& text, const std::string& voice,
                                    float stretch, float f0_hz);

}  // namespace marvin::perception::kws
