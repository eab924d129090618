// marvin-kws-train --embedding: trains the head of the embedding wake word (embedding_head.h)
// for any keyword from synthetic speech (and, as negatives, real recordings of other words).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

int train_embedding_main(int argc, char** argv);

// The sound files (WAV/FLAC/Ogg) of a folder, sorted by name; the first `limit` (0: all).
std::vector<std::filesystem::path> sound_folder_files(const std::filesystem::path& folder,
                                                      std::size_t limit);

// Those files read as 16 kHz mono float in [-1, 1], leading and trailing silence trimmed.
std::vector<std::vector<float>> read_sound_folder(const std::filesystem::path& folder,
                                                  std::size_t limit);
