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

// One sound file as 16 kHz mono float in [-1, 1], leading and trailing silence trimmed. A FLAC
// file with damaged frames is read with them silent, and stderr names it (flac_salvage.h).
std::vector<float> read_recording(const std::filesystem::path& file);

// The folder's sound_folder_files(), each read by read_recording().
std::vector<std::vector<float>> read_sound_folder(const std::filesystem::path& folder,
                                                  std::size_t limit);
