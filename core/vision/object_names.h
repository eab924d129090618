// The 80 COCO classes the object detector knows, and the names people use for them
// ("cell phone" is a "phone", "tv" a "television"). One table, used for what Marvin says,
// for the labels of vision_look and for the words the speech grammar must know.
#ifndef MARVIN_VISION_OBJECT_NAMES_H_
#define MARVIN_VISION_OBJECT_NAMES_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace marvin::vision {

inline constexpr int kCocoClasses = 80;

// COCO's name of class `index` (0 = "person" ... 79 = "toothbrush"); throws
// std::out_of_range outside 0..79.
const std::string& coco_name(int index);

// What Marvin calls it: "cell phone" -> "phone", "remote" -> "remote control",
// "tv" -> "television", "dining table" -> "table"; unchanged when people say it as COCO does.
// Unknown names come back unchanged.
std::string spoken_name(std::string_view coco);

// The plural: "cup" -> "cups", "person" -> "people", "knife" -> "knives", "skis" -> "skis".
std::string spoken_plural(std::string_view spoken);

// "a cup", "an apple".
std::string with_article(std::string_view spoken);

// The COCO class a user's word means: "phone", "mobile", "cell phone" -> "cell phone",
// "tv", "telly", "television" -> "tv"; nullopt for a word that names no class. Case and a
// trailing plural "s" do not matter. "glasses" alone names no class (spectacles), though
// "glass" and "wine glasses" do.
std::optional<std::string> coco_class_for(std::string_view word);

// Every word and phrase coco_class_for() accepts (for the speech recogniser's vocabulary).
std::vector<std::string> object_words();

}  // namespace marvin::vision

#endif  // MARVIN_VISION_OBJECT_NAMES_H_
