// Node types used only by the tests, registered under "Test*" names.
#include <stdexcept>
#include <thread>

#include "graph/node.h"

namespace marvin::graph {
namespace {

// Forwards int64 packets after yielding the thread a few times: a consumer slower than its
// producer, without any sleep.
class TestSlow : public Node {
 public:
  static void declare(Contract& c) {
    c.option_int("yields", 20, 0);
    c.add_input<int64_t>("in");
    c.add_output<int64_t>("out");
  }
  void open(Context& ctx) override { yields_ = ctx.options().get_int("yields"); }
  void process(Context& ctx) override {
    for (int64_t i = 0; i < yields_; ++i) std::this_thread::yield();
    ctx.emit(0, ctx.take_input(0));
  }

 private:
  int64_t yields_ = 0;
};
MARVIN_REGISTER_NODE(TestSlow, "TestSlow");

// Throws from process() at timestamp "at", or from open() when "in_open" is true.
class TestThrow : public Node {
 public:
  static void declare(Contract& c) {
    c.option_int("at", 5);
    c.option_bool("in_open", false);
    c.add_input("in", "any");
    c.add_output("out", "same_as:in");
  }
  void open(Context& ctx) override {
    at_ = ctx.options().get_int("at");
    if (ctx.options().get_bool("in_open")) throw std::runtime_error("microphone unplugged");
  }
  void process(Context& ctx) override {
    if (ctx.input_timestamp() == at_) throw std::runtime_error("model file is corrupt");
    ctx.emit(0, ctx.take_input(0));
  }

 private:
  int64_t at_ = 0;
};
MARVIN_REGISTER_NODE(TestThrow, "TestThrow");

// Two inputs; emits 1 * (a present) + 2 * (b present) for every timestamp it processes.
class TestJoin : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input("a", "any");
    c.add_input("b", "any");
    c.add_output<int64_t>("out");
  }
  void process(Context& ctx) override {
    ctx.emit(0, int64_t{(ctx.has_input(0) ? 1 : 0) + (ctx.has_input(1) ? 2 : 0)});
  }
};
MARVIN_REGISTER_NODE(TestJoin, "TestJoin");

// Needs an int64 input and an optional bool input; used by validation tests.
class TestNeedsInt : public Node {
 public:
  static void declare(Contract& c) {
    c.option_int("threshold", 10, 0, 100);
    c.option_string("mode", "fast", {"fast", "exact"});
    c.add_input<int64_t>("value");
    c.add_input<bool>("enable", true);
  }
  void process(Context& ctx) override { (void)ctx; }
};
MARVIN_REGISTER_NODE(TestNeedsInt, "TestNeedsInt");

}  // namespace
}  // namespace marvin::graph
