#include "vision/face_gallery.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <stdexcept>

#include "vision/face_embedder.h"

namespace marvin::vision {
namespace {

bool same_name(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

}  // namespace

std::optional<data::Person> FaceGallery::find(const std::string& name) {
  for (auto& p : store_.list_people()) {
    if (same_name(p.name, name)) return p;
  }
  return std::nullopt;
}

std::int64_t FaceGallery::enroll(const std::string& name,
                                 const std::vector<std::vector<float>>& embeddings,
                                 std::string_view who) {
  if (name.empty()) throw std::invalid_argument("name: a person to enrol needs a name");
  if (embeddings.empty()) {
    throw std::invalid_argument("embeddings: no face to enrol for " + name);
  }
  for (std::size_t i = 0; i < embeddings.size(); ++i) {
    if (embeddings[i].size() != static_cast<std::size_t>(kEmbeddingSize)) {
      throw std::invalid_argument("embeddings[" + std::to_string(i) + "]: " +
                                  std::to_string(embeddings[i].size()) + " numbers, expected " +
                                  std::to_string(kEmbeddingSize));
    }
  }
  std::int64_t id;
  std::string stored_name = name;
  if (auto p = find(name)) {
    id = p->id;
    stored_name = p->name;
  } else {
    data::Person person;
    person.name = name;
    id = store_.add_person(person);
  }
  for (const auto& e : embeddings) store_.add_face_embedding(id, kFaceModelId, e);
  store_.log_event("face_enrolled", who,
                   stored_name + ": " + std::to_string(embeddings.size()) + " face embedding(s)");
  return id;
}

bool FaceGallery::forget(const std::string& name, std::string_view who) {
  auto p = find(name);
  if (!p) return false;
  const std::size_t n = store_.face_embeddings(p->id).size();
  store_.remove_person(p->id);
  store_.log_event("face_forgotten", who,
                   p->name + ": " + std::to_string(n) + " face embedding(s) removed");
  return true;
}

bool FaceGallery::rename(const std::string& name, const std::string& new_name,
                         std::string_view who) {
  if (new_name.empty()) throw std::invalid_argument("new name: empty; give the person's name");
  auto p = find(name);
  if (!p) return false;
  if (auto other = find(new_name); other && other->id != p->id) {
    throw std::invalid_argument("new name: " + other->name +
                                " is already enrolled; forget or rename them first");
  }
  store_.rename_person(p->id, new_name);
  store_.log_event("face_renamed", who, p->name + " is now called " + new_name);
  return true;
}

std::vector<GalleryPerson> FaceGallery::list() {
  std::vector<GalleryPerson> out;
  std::map<std::int64_t, int> counts;
  for (const auto& e : store_.face_embeddings()) {
    if (e.model_id == kFaceModelId) ++counts[e.person_id];
  }
  // The log, newest first: the first enrolment event naming a person is their latest.
  const auto events = store_.recent_events(10000);
  for (const auto& p : store_.list_people()) {
    GalleryPerson g;
    g.person_id = p.id;
    g.name = p.name;
    g.embeddings = counts[p.id];
    for (const auto& ev : events) {
      if (ev.kind == "face_enrolled" && ev.message.rfind(p.name + ": ", 0) == 0) {
        g.last_enrolled_by = ev.source;
        g.last_enrolled_utc_ms = ev.time_utc_ms;
        break;
      }
    }
    out.push_back(std::move(g));
  }
  return out;
}

FaceMatch FaceGallery::identify(const std::vector<float>& embedding, float threshold) {
  FaceMatch best;
  std::int64_t best_person = 0;
  for (const auto& e : store_.face_embeddings()) {
    if (e.model_id != kFaceModelId || e.values.size() != embedding.size()) continue;
    const float d = squared_distance(e.values, embedding);
    if (best.distance < 0 || d < best.distance) {
      best.distance = d;
      best_person = e.person_id;
    }
  }
  if (best.distance < 0) return best;
  best.person_id = best_person;
  for (const auto& p : store_.list_people()) {
    if (p.id == best_person) best.name = p.name;
  }
  best.known = best.distance < threshold;
  return best;
}

}  // namespace marvin::vision
