#include "interpret/beyond_reach.h"

#include <initializer_list>
#include <vector>

#include "interpret/normalizer.h"

namespace marvin::interpret {
namespace {

struct Topic {
  // Any of these words or phrases (after normalisation) names the topic.
  std::initializer_list<const char*> words;
  const char* reply;
};

// In order: the first topic with a word in the utterance answers. Messages come before the
// internet ("send an e-mail"), shopping before it too ("buy more milk online").
const Topic kTopics[] = {
    {{"text", "texts", "sms", "whatsapp", "message", "messages", "email", "emails", "e-mail",
      "mail"},
     "Sorry, I can't send or read messages. I can call someone for you: say \"call\" and "
     "their name."},
    {{"weather", "forecast", "raining", "rain", "rainy", "snow", "snowing", "sunny",
      "windy", "cloudy", "storm", "frost", "frosty"},
     "Sorry, I can't tell you the weather: I work without the internet."},
    {{"news", "headlines", "newspaper"},
     "Sorry, I can't read you the news: I work without the internet."},
    {{"music", "song", "songs", "radio", "podcast", "playlist", "album", "spotify"},
     "Sorry, I can't play music or the radio."},
    {{"joke", "jokes"}, "Sorry, I don't know any jokes."},
    {{"bus", "buses", "train", "trains", "flight", "flights", "traffic", "stock", "stocks",
      "shares", "bitcoin", "currency", "exchange"},
     "Sorry, I can't look that up: I work without the internet."},
    {{"buy", "purchase", "shopping", "amazon", "takeaway", "groceries", "pizza", "delivery",
      "order me", "order us", "order some", "order a", "order an"},
     "Sorry, I can't buy or order things, and I don't keep a shopping list."},
    {{"google", "internet", "online", "wikipedia", "website", "web", "recipe", "recipes"},
     "Sorry, I can't look things up: I work without the internet."},
    // Taking them: "paint me a picture" is no photo.
    {{"photo", "photos", "photograph", "selfie", "take a picture", "take pictures",
      "take a video", "film me", "record a video"},
     "Sorry, I can't take photos for you. I can tell you what I see: ask \"what do you "
     "see\"."},
    {{"follow", "following"},
     "Sorry, I can't follow you yet. Say \"come here\" and I'll come to you."},
};

}  // namespace

std::optional<std::string> beyond_reach(std::string_view utterance) {
  // Spaces around every word: " order me " is then a plain search, never part of a word.
  const std::vector<std::string> words = normalize(utterance);
  const std::string said = " " + join_words(words, 0, words.size()) + " ";
  for (const Topic& topic : kTopics) {
    for (const char* phrase : topic.words) {
      if (said.find(" " + std::string(phrase) + " ") != std::string::npos) return topic.reply;
    }
  }
  return std::nullopt;
}

}  // namespace marvin::interpret
