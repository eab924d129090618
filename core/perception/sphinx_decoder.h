// Internal: creating pocketsphinx decoders. Not part of the perception API (it includes the
// C headers); used by the wake word and the recognizer.
#pragma once

#include <pocketsphinx.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "perception/sphinx_model.h"

namespace marvin::perception::detail {

struct DecoderDeleter {
  void operator()(ps_decoder_t* decoder) const { ps_free(decoder); }
};
using Decoder = std::unique_ptr<ps_decoder_t, DecoderDeleter>;

// A decoder for `model` with extra command-line style settings ({"-kws_threshold", "1e-30"}).
// Pocketsphinx's own log is discarded. Throws std::runtime_error naming the model paths.
Decoder make_decoder(const SphinxModel& model,
                     const std::vector<std::pair<std::string, std::string>>& settings = {});

}  // namespace marvin::perception::detail
