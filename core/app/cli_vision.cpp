// `marvin people enroll NAME PHOTO...`, `marvin people forget NAME`, `marvin people rename
// NAME NEW_NAME` (the face gallery of core/vision; `marvin people list` is in cli_data.cpp),
// and `marvin vision look CAMERA`: the faces a camera (or a folder of photos) shows, with
// names, as JSON lines.
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/cli.h"
#include "data/sqlite_store.h"
#include "vision/cameras.h"
#include "vision/face_gallery.h"
#include "vision/face_pipeline.h"
#include "vision/object_detector.h"

namespace marvin::app {
namespace {

struct VisionArgs {
  std::string data_dir;
  std::string detector = "blazeface";
  std::string name;
  std::string new_name;
  std::vector<std::string> photos;
  std::string camera;
  int frames = 1;
  double threshold = vision::kDefaultFaceThreshold;
  void add_data_dir(CLI::App& cmd) {
    cmd.add_option("--data-dir", data_dir,
                   "Directory holding marvin.db (default: $MARVIN_DATA_DIR, "
                   "$XDG_DATA_HOME/marvin, ~/.local/share/marvin)");
  }
  data::SqliteStore open() const {
    data::StoreOptions o;
    o.path = data::database_path(data_dir.empty() ? data::default_data_dir()
                                                  : std::filesystem::path(data_dir));
    return data::SqliteStore(o);
  }
};

void enroll(const VisionArgs& a) {
  // Every photo is read and embedded before anything is stored: a bad photo changes nothing.
  vision::FacePipeline pipeline(a.detector);
  std::vector<std::vector<float>> embeddings;
  for (const auto& photo : a.photos) {
    try {
      embeddings.push_back(
          vision::lone_face_embedding(pipeline, vision::read_photo(photo), photo, a.name));
    } catch (const std::invalid_argument& e) {
      throw CliError(std::string(e.what()) + "; nothing was enrolled");
    }
  }
  data::SqliteStore store = a.open();
  vision::FaceGallery gallery(store);
  gallery.enroll(a.name, embeddings, "cli");
  std::printf("enrolled %s from %zu photo%s\n", a.name.c_str(), embeddings.size(),
              embeddings.size() == 1 ? "" : "s");
}

void forget(const VisionArgs& a) {
  data::SqliteStore store = a.open();
  vision::FaceGallery gallery(store);
  if (!gallery.forget(a.name, "cli")) {
    throw CliError("nobody called " + a.name + " is enrolled (see `marvin people list`)");
  }
  std::printf("forgot %s and their face embeddings\n", a.name.c_str());
}

void rename(const VisionArgs& a) {
  data::SqliteStore store = a.open();
  vision::FaceGallery gallery(store);
  try {
    if (!gallery.rename(a.name, a.new_name, "cli")) {
      throw CliError("nobody called " + a.name + " is enrolled (see `marvin people list`)");
    }
  } catch (const std::invalid_argument& e) {
    throw CliError(e.what(), 2);
  }
  std::printf("%s is now called %s\n", a.name.c_str(), a.new_name.c_str());
}

void look(const VisionArgs& a) {
  vision::FacePipeline pipeline(a.detector);
  vision::ObjectDetector objects;
  data::SqliteStore store = a.open();
  vision::FaceGallery gallery(store);
  auto camera = vision::open_camera(a.camera);
  vision::Frame frame;
  for (int i = 0; i < a.frames && camera->read(frame); ++i) {
    nlohmann::json faces = nlohmann::json::array();
    for (const auto& f : pipeline.faces(frame.image)) {
      const auto m = gallery.identify(f.embedding, static_cast<float>(a.threshold));
      faces.push_back({{"name", m.known ? m.name : ""},
                       {"distance", m.distance},
                       {"score", f.score},
                       {"box", {f.box.x, f.box.y, f.box.width, f.box.height}}});
    }
    nlohmann::json things = nlohmann::json::array();
    for (const auto& o : objects.detect(frame.image)) {
      things.push_back({{"label", o.label},
                        {"class", o.coco},
                        {"score", o.score},
                        {"box", {o.box.x, o.box.y, o.box.width, o.box.height}}});
    }
    write_line(
        nlohmann::json{{"frame", frame.index}, {"faces", faces}, {"objects", things}}.dump());
  }
}

void install_vision(CLI::App& root) {
  CLI::App& people = command_group(root, "people", "The people Marvin knows by face");
  {
    auto a = std::make_shared<VisionArgs>();
    auto* cmd = people.add_subcommand("enroll", "Learn a person's face from photos of them alone");
    cmd->add_option("NAME", a->name, "the person's name")->required();
    cmd->add_option("PHOTO", a->photos, "photos showing only this person")->required();
    cmd->add_option("--detector", a->detector, "blazeface (default), blazeface-front or haar");
    a->add_data_dir(*cmd);
    cmd->callback([a] { enroll(*a); });
  }
  {
    auto a = std::make_shared<VisionArgs>();
    auto* cmd = people.add_subcommand("forget", "Remove a person and all their face embeddings");
    cmd->add_option("NAME", a->name, "the person's name")->required();
    a->add_data_dir(*cmd);
    cmd->callback([a] { forget(*a); });
  }
  {
    auto a = std::make_shared<VisionArgs>();
    auto* cmd = people.add_subcommand("rename", "Call an enrolled person by another name");
    cmd->add_option("NAME", a->name, "the person's name now")->required();
    cmd->add_option("NEW_NAME", a->new_name, "the name to use from now on")->required();
    a->add_data_dir(*cmd);
    cmd->callback([a] { rename(*a); });
  }
  CLI::App& vision_cmd = command_group(root, "vision", "Cameras and what they see");
  {
    auto a = std::make_shared<VisionArgs>();
    auto* cmd = vision_cmd.add_subcommand("look", "Faces (with names) and COCO objects a camera sees, as JSON lines");
    cmd->add_option("CAMERA", a->camera, "folder:DIR, video:FILE, device:/dev/video0 or device:0")
        ->required();
    cmd->add_option("--frames", a->frames, "frames to look at (default 1)");
    cmd->add_option("--detector", a->detector, "blazeface (default), blazeface-front or haar");
    cmd->add_option("--threshold", a->threshold, "squared L2 below which a face is known");
    a->add_data_dir(*cmd);
    cmd->callback([a] { look(*a); });
  }
}

}  // namespace

MARVIN_CLI_COMMANDS(install_vision);

}  // namespace marvin::app
