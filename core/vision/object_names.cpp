#include "vision/object_names.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <stdexcept>

namespace marvin::vision {
namespace {

const std::array<std::string, kCocoClasses>& coco_names() {
  static const std::array<std::string, kCocoClasses> names = {
      "person",        "bicycle",      "car",
      "motorcycle",    "airplane",     "bus",
      "train",         "truck",        "boat",
      "traffic light", "fire hydrant", "stop sign",
      "parking meter", "bench",        "bird",
      "cat",           "dog",          "horse",
      "sheep",         "cow",          "elephant",
      "bear",          "zebra",        "giraffe",
      "backpack",      "umbrella",     "handbag",
      "tie",           "suitcase",     "frisbee",
      "skis",          "snowboard",    "sports ball",
      "kite",          "baseball bat", "baseball glove",
      "skateboard",    "surfboard",    "tennis racket",
      "bottle",        "wine glass",   "cup",
      "fork",          "knife",        "spoon",
      "bowl",          "banana",       "apple",
      "sandwich",      "orange",       "broccoli",
      "carrot",        "hot dog",      "pizza",
      "donut",         "cake",         "chair",
      "couch",         "potted plant", "bed",
      "dining table",  "toilet",       "tv",
      "laptop",        "mouse",        "remote",
      "keyboard",      "cell phone",   "microwave",
      "oven",          "toaster",      "sink",
      "refrigerator",  "book",         "clock",
      "vase",          "scissors",     "teddy bear",
      "hair drier",    "toothbrush"};
  return names;
}

// COCO name -> what Marvin says, then other words people use for it.
struct Naming {
  const char* coco;
  const char* spoken;
  std::vector<const char*> also;
};

const std::vector<Naming>& namings() {
  static const std::vector<Naming> table = {
      {"cell phone", "phone", {"mobile", "mobile phone", "smartphone", "telephone"}},
      {"remote", "remote control", {"remote", "tv remote", "clicker"}},
      {"tv", "television", {"tv", "telly", "tv set", "screen"}},
      {"dining table", "table", {"kitchen table", "dining table"}},
      {"couch", "sofa", {"couch", "settee"}},
      {"potted plant", "plant", {"pot plant", "houseplant", "flower pot"}},
      {"refrigerator", "fridge", {"refrigerator"}},
      {"hair drier", "hair dryer", {"hairdryer", "hair drier"}},
      {"sports ball", "ball", {"football", "sports ball"}},
      {"mouse", "computer mouse", {"mouse"}},
      {"laptop", "laptop", {"computer", "notebook"}},
      {"motorcycle", "motorbike", {"motorcycle"}},
      {"airplane", "plane", {"airplane", "aeroplane"}},
      {"donut", "doughnut", {"donut"}},
      {"cup", "cup", {"mug"}},
      {"handbag", "handbag", {"bag", "purse"}},
      {"bicycle", "bicycle", {"bike"}},
      {"wine glass", "glass", {"wine glass"}},
      {"teddy bear", "teddy bear", {"teddy"}},
      {"person", "person", {"people", "someone", "man", "woman"}},
  };
  return table;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool ends_with(const std::string& s, std::string_view end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

}  // namespace

const std::string& coco_name(int index) {
  if (index < 0 || index >= kCocoClasses) {
    throw std::out_of_range("COCO class " + std::to_string(index) + " (expected 0..79)");
  }
  return coco_names()[static_cast<std::size_t>(index)];
}

std::string spoken_name(std::string_view coco) {
  for (const auto& n : namings()) {
    if (coco == n.coco) return n.spoken;
  }
  return std::string(coco);
}

std::string spoken_plural(std::string_view spoken) {
  std::string s(spoken);
  if (s == "person") return "people";
  if (s == "skis" || s == "scissors" || s == "sheep" || s == "broccoli") return s;
  if (ends_with(s, "knife")) return s.substr(0, s.size() - 2) + "ves";
  if (ends_with(s, "sh") || ends_with(s, "ch") || ends_with(s, "s") || ends_with(s, "x")) {
    return s + "es";
  }
  return s + "s";
}

std::string with_article(std::string_view spoken) {
  const bool vowel = !spoken.empty() && std::string_view("aeiou").find(static_cast<char>(
                                            std::tolower(static_cast<unsigned char>(spoken[0])))) !=
                                            std::string_view::npos;
  return std::string(vowel ? "an " : "a ") + std::string(spoken);
}

std::optional<std::string> coco_class_for(std::string_view word) {
  const std::string w = lower(word);
  // "My glasses" are spectacles, which COCO has no class for: looking for wine glasses
  // instead would be wrong, and a taught object can be ("these are my glasses").
  if (w == "glasses") return std::nullopt;
  auto match = [&](const std::string& candidate) -> bool {
    return w == candidate || w == spoken_plural(candidate);
  };
  for (const auto& n : namings()) {
    if (match(n.spoken) || match(n.coco)) return std::string(n.coco);
    for (const char* a : n.also) {
      if (match(a)) return std::string(n.coco);
    }
  }
  for (const auto& c : coco_names()) {
    if (match(c)) return c;
  }
  return std::nullopt;
}

std::vector<std::string> object_words() {
  std::vector<std::string> words;
  for (const auto& c : coco_names()) {
    words.push_back(spoken_name(c));
    words.push_back(c);
  }
  for (const auto& n : namings()) {
    for (const char* a : n.also) words.emplace_back(a);
  }
  std::sort(words.begin(), words.end());
  words.erase(std::unique(words.begin(), words.end()), words.end());
  return words;
}

}  // namespace marvin::vision
