// marvin-kws-train --embedding: trains the head of the embedding wake word (embedding_head.h)
// for any keyword from synthetic speech (and, as negatives, real recordings of other words).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

int train_embedding_main(int argc, char** argv);

// Sound files (WAV/FLAC/...) of a folder, sorted, read as 16 kHz mono float in [-1, 1].
std::vector<std::vector<float>> read_sound_folder(const std::filesystem::path& folder,
                                                  std::size_t limit);
