// `marvin world render --world FILE [--out map.png] [--to PLACE]`: checks a world file and
// draws its floor plan, the robot at its start pose, its sonar rays and camera field of view,
// and (with --to) the path it would take there.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/cli.h"
#include "navigation/navigator.h"
#include "sim/camera.h"
#include "sim/render.h"
#include "sim/simulator.h"
#include "sim/world.h"

namespace marvin::app {
namespace {

struct RenderOptions {
  std::string world;
  std::string out = "map.png";
  std::string to;
  double pixels_per_m = 60;
  std::string camera;        // also write what the camera sees
  std::vector<double> pose;  // x y heading_deg: the robot here instead of its start
  int head_deg = 0;
};

void render(const RenderOptions& o) {
  sim::World world;
  try {
    world = sim::load_world(o.world.empty() ? sim::default_world_file()
                                            : std::filesystem::path(o.world));
  } catch (const sim::WorldError& e) {
    throw CliError(e.what(), 1);
  }
  if (!o.pose.empty()) {
    world.robot.start = {o.pose[0], o.pose[1], o.pose[2] * navigation::kPi / 180};
  }
  sim::Simulator sim(world);
  sim.step(1.0);  // one sweep of the sonar
  std::vector<navigation::Vec2> path;
  if (!o.to.empty()) {
    std::optional<navigation::Target> target = world.map.find(o.to);
    if (!target)
      throw CliError(
          "--to: \"" + o.to + "\" is not a room, place or person of " + world.file.string(), 1);
    navigation::OccupancyGrid grid(world.map, 0.05, navigation::NavigatorOptions{}.inflate_m);
    navigation::Planner planner;
    auto planned = planner.plan(grid, world.robot.start.position(), target->at);
    if (!planned) throw CliError("no path from the robot's start to " + target->name, 1);
    path = *planned;
  }
  sim::MapView view;
  view.pixels_per_m = o.pixels_per_m;
  try {
    sim::write_png(sim::render_map(world, sim::robot_view(sim, path), view), o.out);
  } catch (const std::exception& e) {
    throw CliError(e.what(), 1);
  }
  if (!o.camera.empty()) {
    try {
      sim::SimCamera camera(world, [&] {
        return sim::CameraView{world.robot.start, 1.0 * o.head_deg, 0};
      });
      vision::Frame frame;
      camera.read(frame);
      sim::write_png(frame.image, o.camera);
    } catch (const std::exception& e) {
      throw CliError(e.what(), 1);
    }
    write_line("wrote " + o.camera + " (the camera's view)");
  }
  write_line("wrote " + o.out + " (" + std::to_string(world.map.rooms.size()) + " rooms, " +
             std::to_string(world.map.furniture.size()) + " pieces of furniture" +
             (path.empty() ? "" : ", a path of " + std::to_string(path.size()) + " waypoints") +
             ")");
}

void install_world_commands(CLI::App& root) {
  CLI::App& world = command_group(root, "world", "The simulated home: world files and pictures");
  auto options = std::make_shared<RenderOptions>();
  CLI::App* r = world.add_subcommand("render", "Check a world file and draw its floor plan");
  r->add_option("--world", options->world, "The world file (default: examples/worlds/home.json)");
  r->add_option("--out", options->out, "The PNG to write (default: map.png)");
  r->add_option("--to", options->to, "Also draw the path from the robot's start to this place");
  r->add_option("--scale", options->pixels_per_m, "Pixels per metre (default 60)")
      ->check(CLI::Range(5.0, 400.0));
  r->add_option("--camera", options->camera, "Also write what the robot's camera sees (PNG)");
  r->add_option("--pose", options->pose, "Put the robot at X Y HEADING_DEG instead of its start")
      ->expected(3);
  r->add_option("--head", options->head_deg, "Head tilt for --camera, degrees above level")
      ->check(CLI::Range(-60, 60));
  r->callback([options] { render(*options); });
}

}  // namespace

MARVIN_CLI_COMMANDS(install_world_commands);

}  // namespace marvin::app
