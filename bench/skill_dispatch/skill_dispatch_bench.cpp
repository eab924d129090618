// Native skill dispatch overhead (goal: under 5 us per request).
//
// Measures, in one run, per request:
//   baseline   a direct virtual call of the same C++ skill handler (no ABI, no host);
//   c_abi      the descriptor's handle() through the C ABI, as the loader calls it (the C++
//              layer builds the Request and parses "{}" / a one-slot JSON);
//   instance   SkillInstance::handle() from the native loader (what the manager calls),
//              the skill making one Robot API call (now()) through the host's table;
// and prints each with its ratio to the baseline. Never fails on time.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <marvin/skill.hpp>
#include <vector>

#include "skills/host_api.h"
#include "skills/native_runtime.h"

namespace {

class Counter : public marvin::Skill {
 public:
  using Skill::Skill;
  void handle(const marvin::Request& request) override {
    sink_ += request.intent.size();
    if (request.intent == "now") sink_ += static_cast<std::size_t>(robot().now_ms() & 1);
  }
  std::size_t sink_ = 0;
};

using Clock = std::chrono::steady_clock;

template <class F>
double median_ns_per_call(F&& body, int calls) {
  std::vector<double> runs;
  for (int run = 0; run < 9; ++run) {
    auto start = Clock::now();
    for (int i = 0; i < calls; ++i) body();
    auto end = Clock::now();
    runs.push_back(std::chrono::duration<double, std::nano>(end - start).count() / calls);
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}

}  // namespace

int main() {
  marvin::skills::HostServices services;
  services.now_ms = [] { return std::int64_t{1767603600000}; };
  marvin::skills::SkillContext context("counter", {}, services);
  marvin::skills::Manifest manifest;
  manifest.id = "counter";
  const marvin_skill_descriptor* d = marvin::skill_descriptor<Counter>("counter");
  constexpr int kCalls = 200000;

  // Baseline: the handler called directly.
  Counter direct(marvin::Robot(marvin::skills::host_robot_api(), context.host()));
  marvin::Skill* as_base = &direct;
  marvin::Request request{"roll", nlohmann::json::object(), "roll a die"};
  double baseline = median_ns_per_call([&] { as_base->handle(request); }, kCalls);
  // Second baseline: the same work the C++ layer does for a request (build it, parse the
  // slots), still without the ABI: most of the dispatch cost is this JSON work.
  double baseline_parse = median_ns_per_call(
      [&] {
        marvin::Request r{"roll", nlohmann::json::parse("{\"count\":3}"), "roll 3 dice"};
        as_base->handle(r);
      },
      kCalls);

  // Through the C ABI.
  char buffer[256];
  void* instance = d->create(marvin::skills::host_robot_api(), context.host(), nullptr);
  marvin_request c_request{sizeof(marvin_request), "roll", "{}", "roll a die"};
  double c_abi = median_ns_per_call(
      [&] {
        marvin_text_out error{buffer, sizeof buffer, 0};
        d->handle(instance, &c_request, &error);
      },
      kCalls);
  marvin_request slot_request{sizeof(marvin_request), "roll", "{\"count\":3}", "roll 3 dice"};
  double c_abi_slot = median_ns_per_call(
      [&] {
        marvin_text_out error{buffer, sizeof buffer, 0};
        d->handle(instance, &slot_request, &error);
      },
      kCalls);
  d->destroy(instance);

  // What the skill manager calls: the loader's instance, plus one Robot API call.
  auto loaded = marvin::skills::make_native_instance(d, manifest, marvin::skills::host_robot_api(),
                                                     context.host());
  marvin_request now_request{sizeof(marvin_request), "now", "{}", "what time is it"};
  std::string error;
  double with_api = median_ns_per_call(
      [&] {
        context.begin_request();
        loaded->handle(now_request, &error);
      },
      kCalls);

  std::printf("native skill dispatch, median of 9 runs x %d calls (goal: < 5000 ns)\n", kCalls);
  std::printf("  %-46s %8.1f ns  x%.1f\n", "baseline: direct Skill::handle()", baseline, 1.0);
  std::printf("  %-46s %8.1f ns  x%.1f\n", "baseline 2: build Request + parse slots, direct",
              baseline_parse, baseline_parse / baseline);
  std::printf("  %-46s %8.1f ns  x%.1f\n", "C ABI handle(), slots \"{}\"", c_abi, c_abi / baseline);
  std::printf("  %-46s %8.1f ns  x%.1f\n", "C ABI handle(), slots {\"count\":3}", c_abi_slot,
              c_abi_slot / baseline);
  std::printf("  %-46s %8.1f ns  x%.1f\n", "SkillInstance::handle() + one Robot API call", with_api,
              with_api / baseline);
  std::printf(
      "overhead over the direct call: %.1f ns (C ABI, with a slot), %.1f ns (manager's call)\n",
      c_abi_slot - baseline, with_api - baseline);
  return 0;
}
