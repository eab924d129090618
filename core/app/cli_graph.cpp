// `marvin graph run|check|dot FILE.json`: run, validate or draw a perception graph.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "app/cli.h"
#include "graph/graph.h"
#include "perception/voice_nodes.h"
#include "vision/vision_nodes.h"

namespace marvin::app {
namespace {

using graph::Graph;
using graph::GraphError;

struct RunArgs {
  std::string file;
  double seconds = 0;
  int threads = 0;
  std::string trace;
};

// Loads and validates; a bad file is the user's error, reported as given (exit code 2).
graph::GraphConfig load(const std::string& file) {
  try {
    return graph::load_graph_config(file);
  } catch (const GraphError& e) {
    throw CliError(e.what(), 2);
  }
}

std::unique_ptr<Graph> build(const std::string& file, graph::GraphOptions options = {}) {
  graph::GraphConfig config = load(file);
  try {
    return std::make_unique<Graph>(std::move(config), options);
  } catch (const GraphError& e) {
    throw CliError(file + ": invalid graph:\n" + e.what(), 2);
  }
}

void run(const RunArgs& args) {
  graph::GraphOptions options;
  options.threads = args.threads;
  options.trace = !args.trace.empty();
  std::unique_ptr<Graph> g = build(args.file, options);
  const auto start = std::chrono::steady_clock::now();
  g->start();
  std::string failure;
  try {
    if (args.seconds > 0 &&
        !g->wait_for(std::chrono::duration_cast<std::chrono::nanoseconds>(
            std::chrono::duration<double>(args.seconds)))) {
      g->stop();  // time is up: sources finish, streams drain
    }
    g->wait();
  } catch (const GraphError& e) {
    failure = e.what();
  }
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("graph %s ran %.2f s on %d threads\n\n%s", args.file.c_str(), elapsed, g->threads(),
              g->stats().to_text().c_str());
  if (!args.trace.empty()) {
    g->write_trace(args.trace);
    std::printf("trace written to %s\n", args.trace.c_str());
  }
  std::fflush(stdout);
  if (!failure.empty()) throw CliError(failure, 1);
}

void install_graph(CLI::App& root) {
  // The voice nodes live in a static library; register them explicitly so graph files can
  // name them (a registration object in an unreferenced archive member is dropped).
  perception::register_voice_nodes();
  vision::register_vision_nodes();
  CLI::App* group = root.add_subcommand("graph", "Run, check or draw a perception graph (JSON)");
  group->require_subcommand(1);

  auto args = std::make_shared<RunArgs>();
  CLI::App* run_cmd = group->add_subcommand("run", "Run a graph, then print its counters");
  run_cmd->add_option("FILE", args->file, "graph JSON file")->required();
  run_cmd->add_option("--for", args->seconds, "stop after SECONDS (default: until it finishes)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_option("--threads", args->threads, "worker threads (default: the graph's)")
      ->check(CLI::Range(1, 256));
  run_cmd->add_option("--trace", args->trace, "write a Chrome trace (JSON) of node spans to FILE");
  run_cmd->callback([args] { run(*args); });

  auto check_file = std::make_shared<std::string>();
  CLI::App* check_cmd = group->add_subcommand("check", "Validate a graph without running it");
  check_cmd->add_option("FILE", *check_file, "graph JSON file")->required();
  check_cmd->callback([check_file] {
    graph::GraphOptions options;
    options.watchdog_thread = false;
    const graph::GraphConfig config = load(*check_file);
    build(*check_file, options);
    std::printf("%s: valid (%zu nodes, %zu streams)\n", check_file->c_str(), config.nodes.size(),
                config.streams.size());
  });

  auto dot_file = std::make_shared<std::string>();
  CLI::App* dot_cmd = group->add_subcommand("dot", "Print a graph in Graphviz dot format");
  dot_cmd->add_option("FILE", *dot_file, "graph JSON file")->required();
  dot_cmd->callback([dot_file] { std::fputs(build(*dot_file)->to_dot().c_str(), stdout); });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_graph);

}  // namespace marvin::app
