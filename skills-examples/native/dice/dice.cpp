// Example native skill: rolls dice. Shows the SDK's pieces a skill author needs: a class
// and the MARVIN_SKILL macro, a typed slot the skill manager asks for when it is missing
// ("roll some dice" -> "How many dice?"), the robot's clock, and per-skill storage
// ("what did I roll?").
#include <cstdint>
#include <marvin/skill.hpp>
#include <string>
#include <vector>

namespace {

constexpr int kMaxDice = 10;

class Dice : public marvin::Skill {
 public:
  // The generator is seeded from the robot's clock: a MockRobot's fixed clock makes tests
  // repeatable.
  explicit Dice(marvin::Robot robot)
      : marvin::Skill(robot), state_(static_cast<std::uint64_t>(this->robot().now_ms()) | 1u) {}

  void handle(const marvin::Request& request) override {
    if (request.intent == "last_roll") {
      std::optional<std::string> last = robot().storage_get("last_roll");
      robot().say(last ? "Last time you rolled " + *last + "." : "You haven't rolled yet.");
      return;
    }
    int count = 1;
    if (request.intent == "roll_many") {
      double wanted = request.slots.at("count").get<double>();
      if (wanted < 1 || wanted > kMaxDice || wanted != static_cast<int>(wanted)) {
        robot().say("I can roll one to ten dice.");
        return;
      }
      count = static_cast<int>(wanted);
    }
    std::vector<int> rolls;
    int total = 0;
    for (int i = 0; i < count; ++i) {
      rolls.push_back(roll());
      total += rolls.back();
    }
    std::string sentence;
    if (count == 1) {
      sentence = "You rolled a " + std::to_string(total) + ".";
    } else {
      sentence = "You rolled ";
      for (std::size_t i = 0; i < rolls.size(); ++i) {
        if (i > 0) sentence += i + 1 == rolls.size() ? " and " : ", ";
        sentence += std::to_string(rolls[i]);
      }
      sentence += ": " + std::to_string(total) + " in total.";
    }
    robot().storage_set("last_roll", std::to_string(total));
    robot().say(sentence);
  }

 private:
  int roll() {
    // xorshift64*: small, good enough for dice, and the same on every platform.
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    return static_cast<int>((state_ * 2685821657736338717ull) >> 33) % 6 + 1;
  }

  std::uint64_t state_;
};

}  // namespace

MARVIN_SKILL(Dice, "dice")
