// FaceGallery: the people Marvin knows by face, in the owner's SQLite store (the people and
// face_embeddings tables of core/data). Several embeddings per person; identification is
// the nearest enrolled embedding by squared L2 distance, accepted below a threshold, else
// "unknown" (as the original robot did).
//
// Who added a face and when: every enrolment and every forget is written to the store's
// event log (kind "face_enrolled" / "face_forgotten", source = who, e.g. "cli" or
// "voice:owner", stamped by the store), so the people tables keep their schema. Photos are
// never stored, only the 128 numbers.
#ifndef MARVIN_VISION_FACE_GALLERY_H_
#define MARVIN_VISION_FACE_GALLERY_H_

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "data/sqlite_store.h"

namespace marvin::vision {

// Squared L2 below which two embeddings are taken as the same person. Calibrated on the ORL
// dev faces (core/vision/README.md has the sweep): 0 false accepts, 100% true accepts there.
inline constexpr float kDefaultFaceThreshold = 0.22f;

struct FaceMatch {
  bool known = false;          // distance below the threshold
  std::string name;            // the nearest person (also when not known), or empty
  std::int64_t person_id = 0;
  float distance = -1;         // squared L2 to the nearest enrolled embedding; -1: gallery empty
};

struct GalleryPerson {
  std::int64_t person_id = 0;
  std::string name;
  int embeddings = 0;
  std::string last_enrolled_by;      // from the event log; empty if unknown
  std::int64_t last_enrolled_utc_ms = 0;
};

class FaceGallery {
 public:
  explicit FaceGallery(data::SqliteStore& store) : store_(store) {}

  // Adds `embeddings` (each kEmbeddingSize numbers) to the person called `name` (matched
  // without regard to case), creating the person if needed. Throws std::invalid_argument
  // naming the field for an empty name, no embeddings or a wrong size; nothing is stored then.
  std::int64_t enroll(const std::string& name, const std::vector<std::vector<float>>& embeddings,
                      std::string_view who);
  // Removes the person and all their embeddings; false if nobody has that name.
  bool forget(const std::string& name, std::string_view who);
  // Calls the person `name` `new_name` from now on (their faces stay); logged as
  // "face_renamed". False if nobody has that name. Throws std::invalid_argument naming the
  // field when `new_name` is empty or already someone else's; nothing changes then.
  bool rename(const std::string& name, const std::string& new_name, std::string_view who);
  std::vector<GalleryPerson> list();
  FaceMatch identify(const std::vector<float>& embedding,
                     float threshold = kDefaultFaceThreshold);
  std::optional<data::Person> find(const std::string& name);

 private:
  data::SqliteStore& store_;
};

}  // namespace marvin::vision

#endif  // MARVIN_VISION_FACE_GALLERY_H_
