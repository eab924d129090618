#include "vision/vision_nodes.h"

#include <chrono>
#include <cstdio>
#include <memory>

#include "common/log.h"
#include "data/sqlite_store.h"
#include "graph/node.h"
#include "vision/cameras.h"
#include "vision/face_detector.h"
#include "vision/face_embedder.h"
#include "vision/face_gallery.h"

namespace marvin::vision {
namespace {

using graph::Context;
using graph::Contract;
using graph::Node;
using graph::Timestamp;

class CameraSource : public Node {
 public:
  static void declare(Contract& c) {
    c.add_output<Frame>("frames");
    c.option_string("camera", "");
    c.option_int("width", 640, 0, 8192);
    c.option_int("height", 480, 0, 8192);
    c.option_double("fps", 30, 0, 1000);
    c.option_double("pace_fps", 0, 0, 1000);
    c.option_bool("loop", false);
    c.option_int("retry_ms", 1000, 1, 600'000);
    c.option_int("max_frames", 0, 0, INT64_MAX);
  }
  void open(Context& ctx) override {
    const auto& o = ctx.options();
    spec_ = o.get_string("camera");
    if (spec_.empty()) throw std::runtime_error("CameraSource: option \"camera\" is required");
    width_ = static_cast<int>(o.get_int("width"));
    height_ = static_cast<int>(o.get_int("height"));
    fps_ = o.get_double("fps");
    pace_fps_ = o.get_double("pace_fps");
    loop_ = o.get_bool("loop");
    retry_ = std::chrono::milliseconds(o.get_int("retry_ms"));
    max_frames_ = static_cast<uint64_t>(o.get_int("max_frames"));
    try_open(ctx);  // a camera missing at start is retried like one that vanishes later
  }
  void process(Context& ctx) override {
    if (ctx.stop_requested() || (max_frames_ > 0 && emitted_ >= max_frames_)) {
      ctx.finish();
      return;
    }
    if (!camera_ && !try_open(ctx)) {
      ctx.wake_after(retry_);
      return;
    }
    Frame frame;
    try {
      if (!camera_->read(frame)) {
        if (!loop_) {
          ctx.finish();
          return;
        }
        camera_.reset();  // reopen: a folder or video starts over
        return;
      }
    } catch (const CameraError& e) {
      log(LogLevel::kWarning, "vision", std::string(e.what()) + "; retrying every " +
                                            std::to_string(retry_.count()) + " ms");
      camera_.reset();
      ctx.wake_after(retry_);
      return;
    }
    // Strictly increasing timestamps across reopenings (a reopened camera counts from 0).
    const Timestamp ts = std::max<Timestamp>(frame.time_us + offset_us_, last_ts_ + 1);
    last_ts_ = ts;
    ctx.emit(0, graph::Packet::make<Frame>(std::move(frame)).at(ts));
    ++emitted_;
    if (pace_fps_ > 0) {
      ctx.wake_after(std::chrono::nanoseconds(static_cast<int64_t>(1e9 / pace_fps_)));
    }
  }

 private:
  bool try_open(Context& ctx) {
    (void)ctx;
    try {
      if (spec_.rfind("folder:", 0) == 0) {
        camera_ = std::make_unique<FolderCamera>(spec_.substr(7), false);
      } else {
        camera_ = open_camera(spec_, width_, height_, fps_);
      }
      offset_us_ = last_ts_ + 1;
      log(LogLevel::kInfo, "vision", "camera open: " + camera_->describe());
      return true;
    } catch (const CameraError& e) {
      log(LogLevel::kWarning, "vision", std::string(e.what()) + "; retrying every " +
                                            std::to_string(retry_.count()) + " ms");
      camera_.reset();
      return false;
    }
  }

  std::string spec_;
  int width_ = 640, height_ = 480;
  double fps_ = 30, pace_fps_ = 0;
  bool loop_ = false;
  std::chrono::milliseconds retry_{1000};
  uint64_t max_frames_ = 0, emitted_ = 0;
  std::unique_ptr<Camera> camera_;
  Timestamp last_ts_ = -1;
  int64_t offset_us_ = 0;
};

class FaceDetectorNode : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<Frame>("in");
    c.add_output<FaceList>("out");
    c.option_string("detector", "blazeface", {"blazeface", "blazeface-front", "haar"});
    c.option_double("min_score", 0.6, 0.0, 1.0);
  }
  void open(Context& ctx) override {
    const std::string kind = ctx.options().get_string("detector");
    const float min_score = static_cast<float>(ctx.options().get_double("min_score"));
    if (kind == "haar") {
      detector_ = std::make_unique<HaarFaceDetector>();
    } else {
      detector_ = std::make_unique<BlazeFaceDetector>(kind == "blazeface-front"
                                                          ? BlazeFaceDetector::Range::kFront128
                                                          : BlazeFaceDetector::Range::kBack256,
                                                      min_score);
    }
  }
  void process(Context& ctx) override {
    const Frame& frame = ctx.input(0).get<Frame>();
    FaceList list;
    list.image = frame.image;
    list.frame_index = frame.index;
    list.faces = detector_->detect(frame.image);
    ctx.emit(0, std::move(list));
  }

 private:
  std::unique_ptr<FaceDetector> detector_;
};

class FaceEmbedderNode : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<FaceList>("in");
    c.add_output<FaceList>("out");
  }
  void open(Context&) override { embedder_ = std::make_unique<FaceEmbedder>(); }
  void process(Context& ctx) override {
    FaceList list = ctx.input(0).get<FaceList>();
    for (Face& f : list.faces) f.embedding = embedder_->embed_chip(face_chip(list.image, f));
    ctx.emit(0, std::move(list));
  }

 private:
  std::unique_ptr<FaceEmbedder> embedder_;
};

class FaceIdentifierNode : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<FaceList>("in");
    c.add_output<FaceList>("out");
    c.option_string("database", "");
    c.option_double("threshold", kDefaultFaceThreshold, 0.0, 100.0);
  }
  void open(Context& ctx) override {
    std::string db = ctx.options().get_string("database");
    const std::filesystem::path path =
        db.empty() ? data::database_path(data::default_data_dir()) : std::filesystem::path(db);
    data::StoreOptions o;
    o.path = path;
    store_ = std::make_unique<data::SqliteStore>(o);
    gallery_ = std::make_unique<FaceGallery>(*store_);
    threshold_ = static_cast<float>(ctx.options().get_double("threshold"));
  }
  void process(Context& ctx) override {
    FaceList list = ctx.input(0).get<FaceList>();
    for (Face& f : list.faces) {
      if (f.embedding.empty()) continue;
      const FaceMatch m = gallery_->identify(f.embedding, threshold_);
      f.distance = m.distance;
      if (m.known) f.name = m.name;
    }
    ctx.emit(0, std::move(list));
  }

 private:
  std::unique_ptr<data::SqliteStore> store_;
  std::unique_ptr<FaceGallery> gallery_;
  float threshold_ = kDefaultFaceThreshold;
};

class FaceLogger : public Node {
 public:
  static void declare(Contract& c) { c.add_input<FaceList>("in"); }
  void process(Context& ctx) override {
    const FaceList& list = ctx.input(0).get<FaceList>();
    std::string line = "frame " + std::to_string(list.frame_index) + ": " +
                       std::to_string(list.faces.size()) + " face(s)";
    for (const Face& f : list.faces) {
      char box[96];
      std::snprintf(box, sizeof box, " [%s at %.0f,%.0f %.0fx%.0f]",
                    f.name.empty() ? (f.embedding.empty() ? "face" : "unknown") : f.name.c_str(),
                    f.box.x, f.box.y, f.box.width, f.box.height);
      line += box;
    }
    log(LogLevel::kInfo, "vision", line);
  }
};

class ObjectDetectorNode : public Node {
 public:
  static void declare(Contract& c) {
    c.add_input<Frame>("in");
    c.add_output<ObjectList>("out");
    c.option_double("min_score", 0.35, 0.0, 1.0);
    c.option_double("nms_iou", 0.5, 0.0, 1.0);
    c.option_string("model", "");
  }
  void open(Context& ctx) override {
    detector_ = std::make_unique<ObjectDetector>(
        ctx.options().get_string("model"), static_cast<float>(ctx.options().get_double("min_score")),
        static_cast<float>(ctx.options().get_double("nms_iou")));
  }
  void process(Context& ctx) override {
    const Frame& frame = ctx.input(0).get<Frame>();
    ObjectList list;
    list.image = frame.image;
    list.frame_index = frame.index;
    list.objects = detector_->detect(frame.image);
    ctx.emit(0, std::move(list));
  }

 private:
  std::unique_ptr<ObjectDetector> detector_;
};

class ObjectLogger : public Node {
 public:
  static void declare(Contract& c) { c.add_input<ObjectList>("in"); }
  void process(Context& ctx) override {
    const ObjectList& list = ctx.input(0).get<ObjectList>();
    std::string line = "frame " + std::to_string(list.frame_index) + ": " +
                       std::to_string(list.objects.size()) + " object(s)";
    for (const DetectedObject& o : list.objects) {
      char box[160];
      std::snprintf(box, sizeof box, " [%s %.2f at %.0f,%.0f %.0fx%.0f]", o.label.c_str(),
                    static_cast<double>(o.score), o.box.x, o.box.y, o.box.width, o.box.height);
      line += box;
    }
    log(LogLevel::kInfo, "vision", line);
  }
};

template <typename N>
void add_node(graph::NodeRegistry& registry, const char* name) {
  if (registry.find(name) != nullptr) return;
  registry.add({name, &N::declare, []() -> std::unique_ptr<Node> { return std::make_unique<N>(); }});
}

}  // namespace

void register_vision_nodes(graph::NodeRegistry& registry) {
  add_node<CameraSource>(registry, "CameraSource");
  add_node<FaceDetectorNode>(registry, "FaceDetectorNode");
  add_node<FaceEmbedderNode>(registry, "FaceEmbedderNode");
  add_node<FaceIdentifierNode>(registry, "FaceIdentifierNode");
  add_node<FaceLogger>(registry, "FaceLogger");
  add_node<ObjectDetectorNode>(registry, "ObjectDetectorNode");
  add_node<ObjectLogger>(registry, "ObjectLogger");
}

}  // namespace marvin::vision
