// marvin-vision-eval: measures and checks the vision models on real photos.
//
//   marvin-vision-eval faces DIR [--enrol N] [--detector D] [--threshold T] [--margin M]
//       DIR has one folder per person. The first half of the people (in name order) are
//       enrolled with their first N photos (3); their other photos are identified (rank-1:
//       the nearest enrolled embedding is theirs; accepted: also below the threshold), and
//       every photo of the other half, never enrolled, is an impostor: a false accept when
//       its nearest embedding is below the threshold. Prints a threshold sweep too.
//       --enrol-second-half enrols the second half instead (the other split).
//   marvin-vision-eval detect IMAGE... [--detector D]
//       The faces found in each image (box, score).
//   marvin-vision-eval chips OUT_DIR IMAGE...
//       For the conversion check (tools/vision/reference_check.mjs): the 150x150 RGB chip of
//       the largest face of each image (OUT_DIR/NAME.rgb, raw bytes) and our embedding
//       (OUT_DIR/ours.json).
//   marvin-vision-eval objects IMAGE...
//       The COCO objects NanoDet finds in each image (label, COCO name, box, score).
//   marvin-vision-eval object-outputs OUT_DIR IMAGE...
//       For the object detector's conversion check (tools/vision/object_reference_check.mjs):
//       the network input of each image (OUT_DIR/NAME.input, float32 1x3x416x416) and our six
//       raw outputs in the TF.js graph's layout [1, cells, C] (OUT_DIR/ours.json).
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "vision/cameras.h"
#include "vision/face_gallery.h"
#include "vision/face_pipeline.h"
#include "vision/object_detector.h"

namespace fs = std::filesystem;
using namespace marvin::vision;

namespace {

struct Args {
  std::vector<std::string> positional;
  int enrol = 3;
  std::string detector = "blazeface-front";
  double threshold = kDefaultFaceThreshold;
  bool second_half = false;
  float margin = 1.25f;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 2; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(s + " needs a value");
      return argv[++i];
    };
    if (s == "--enrol") a.enrol = std::stoi(value());
    else if (s == "--detector") a.detector = value();
    else if (s == "--threshold") a.threshold = std::stod(value());
    else if (s == "--margin") a.margin = std::stof(value());
    else if (s == "--enrol-second-half") a.second_half = true;
    else a.positional.push_back(s);
  }
  return a;
}

std::vector<fs::path> images_in(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && is_image_file(e.path())) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end(), [](const fs::path& x, const fs::path& y) {
    // Numeric names (ORL: 1.pgm .. 10.pgm) in numeric order.
    const std::string a = x.stem().string(), b = y.stem().string();
    if (a.size() != b.size()) return a.size() < b.size();
    return a < b;
  });
  return out;
}

std::vector<float> embed(FacePipeline& p, const fs::path& photo, float margin, int& no_face) {
  const cv::Mat image = read_photo(photo);
  std::vector<Face> found = p.detector().detect(image);
  Face face;
  if (found.empty()) {
    ++no_face;
    face.box = cv::Rect2f(0, 0, static_cast<float>(image.cols), static_cast<float>(image.rows));
    return p.embedder().embed_chip(face_chip(image, face, 1.0f));
  }
  face = *std::max_element(found.begin(), found.end(),
                           [](const Face& x, const Face& y) { return x.box.area() < y.box.area(); });
  return p.embedder().embed_chip(face_chip(image, face, margin));
}

int faces(const Args& a) {
  if (a.positional.size() != 1) throw std::runtime_error("faces: give one DIR");
  std::vector<fs::path> people;
  for (const auto& e : fs::directory_iterator(a.positional[0])) {
    if (e.is_directory()) people.push_back(e.path());
  }
  std::sort(people.begin(), people.end(), [](const fs::path& x, const fs::path& y) {
    const std::string p = x.filename().string(), q = y.filename().string();
    return p.size() != q.size() ? p.size() < q.size() : p < q;
  });
  if (people.size() < 2) throw std::runtime_error("faces: need folders of at least 2 people");
  FacePipeline pipeline(a.detector);
  const std::size_t enrolled_people = people.size() / 2;
  struct Entry { std::size_t person; std::vector<float> e; };
  std::vector<Entry> gallery, genuine, impostor;
  int no_face = 0, photos = 0;
  for (std::size_t p = 0; p < people.size(); ++p) {
    const auto files = images_in(people[p]);
    for (std::size_t i = 0; i < files.size(); ++i) {
      ++photos;
      Entry e{p, embed(pipeline, files[i], a.margin, no_face)};
      const bool enrolled = a.second_half ? p >= people.size() - enrolled_people : p < enrolled_people;
      if (!enrolled) impostor.push_back(std::move(e));
      else if (i < static_cast<std::size_t>(a.enrol)) gallery.push_back(std::move(e));
      else genuine.push_back(std::move(e));
    }
  }
  auto nearest = [&](const std::vector<float>& q) {
    std::pair<float, std::size_t> best{1e30f, 0};
    for (const auto& g : gallery) best = std::min(best, {squared_distance(q, g.e), g.person});
    return best;
  };
  std::size_t rank1 = 0;
  std::vector<std::pair<float, bool>> gen;  // distance, correct
  for (const auto& q : genuine) {
    const auto [d, who] = nearest(q.e);
    rank1 += who == q.person;
    gen.emplace_back(d, who == q.person);
  }
  std::vector<float> imp;
  for (const auto& q : impostor) imp.push_back(nearest(q.e).first);
  auto rates = [&](double t) {
    std::size_t ta = 0, fa = 0;
    for (const auto& [d, ok] : gen) ta += ok && d < t;
    for (float d : imp) fa += d < t;
    return std::pair{100.0 * static_cast<double>(ta) / static_cast<double>(gen.size()),
                     100.0 * static_cast<double>(fa) / static_cast<double>(imp.size())};
  };
  std::printf("faces %s: %zu people, %d photos, detector %s, %d without a detected face (whole "
              "photo used)\n",
              a.positional[0].c_str(), people.size(), photos, pipeline.detector().name().c_str(),
              no_face);
  std::printf("enrolled %zu people x %d photos; %zu genuine probes, %zu impostor probes (%zu "
              "people never enrolled)\n",
              enrolled_people, a.enrol, genuine.size(), impostor.size(),
              people.size() - enrolled_people);
  std::printf("rank-1 identification: %.1f%% (%zu/%zu)\n",
              100.0 * static_cast<double>(rank1) / static_cast<double>(genuine.size()), rank1,
              genuine.size());
  const auto [ta, fa] = rates(a.threshold);
  std::printf("at threshold %.3f (squared L2): true accepts %.1f%%, false accepts %.1f%%\n",
              a.threshold, ta, fa);
  std::printf("sweep: threshold  true-accept%%  false-accept%%\n");
  for (double t = 0.10; t <= 0.401; t += 0.02) {
    const auto [x, y] = rates(t);
    std::printf("       %.2f       %5.1f         %5.1f\n", t, x, y);
  }
  return 0;
}

int detect(const Args& a) {
  auto detector = make_face_detector(a.detector);
  for (const auto& file : a.positional) {
    const cv::Mat image = read_photo(file);
    const auto found = detector->detect(image);
    std::printf("%s (%dx%d): %zu faces\n", file.c_str(), image.cols, image.rows, found.size());
    for (const auto& f : found) {
      std::printf("  box %.0f %.0f %.0f %.0f score %.3f\n", f.box.x, f.box.y, f.box.width,
                  f.box.height, f.score);
    }
  }
  return 0;
}

int chips(const Args& a) {
  if (a.positional.size() < 2) throw std::runtime_error("chips: give OUT_DIR and images");
  const fs::path out = a.positional[0];
  fs::create_directories(out);
  FacePipeline pipeline(a.detector);
  nlohmann::json ours = nlohmann::json::object();
  for (std::size_t i = 1; i < a.positional.size(); ++i) {
    const fs::path file = a.positional[i];
    const cv::Mat image = read_photo(file);
    auto face = pipeline.main_face(image, true);
    const cv::Mat chip = face_chip(image, *face, a.margin);
    cv::Mat rgb;
    cv::cvtColor(chip, rgb, cv::COLOR_BGR2RGB);
    const std::string name = file.stem().string();
    std::ofstream(out / (name + ".rgb"), std::ios::binary)
        .write(reinterpret_cast<const char*>(rgb.data), static_cast<std::streamsize>(rgb.total() * 3));
    ours[name] = pipeline.embedder().embed_chip(chip);
  }
  std::ofstream(out / "ours.json") << ours.dump() << "\n";
  std::printf("wrote %zu chips and ours.json to %s\n", a.positional.size() - 1, out.c_str());
  return 0;
}

int objects(const Args& a) {
  ObjectDetector detector;
  for (const auto& file : a.positional) {
    const cv::Mat image = read_photo(file);
    const auto found = detector.detect(image);
    std::printf("%s (%dx%d): %zu objects\n", file.c_str(), image.cols, image.rows, found.size());
    for (const auto& o : found) {
      std::printf("  %-16s (%s) box %.0f %.0f %.0f %.0f score %.3f\n", o.label.c_str(),
                  o.coco.c_str(), o.box.x, o.box.y, o.box.width, o.box.height, o.score);
    }
  }
  return 0;
}

int object_outputs(const Args& a) {
  if (a.positional.size() < 2) throw std::runtime_error("object-outputs: give OUT_DIR and images");
  const fs::path out = a.positional[0];
  fs::create_directories(out);
  ObjectDetector detector;
  nlohmann::json ours = nlohmann::json::object();
  for (std::size_t i = 1; i < a.positional.size(); ++i) {
    const fs::path file = a.positional[i];
    const cv::Mat blob = ObjectDetector::to_blob(read_photo(file));
    const std::string name = file.stem().string();
    std::ofstream(out / (name + ".input"), std::ios::binary)
        .write(reinterpret_cast<const char*>(blob.ptr<float>()),
               static_cast<std::streamsize>(blob.total() * sizeof(float)));
    nlohmann::json outputs = nlohmann::json::array();
    for (const cv::Mat& m : detector.forward(blob)) {
      // [1, C, H, W] -> [H*W, C], the graph's own output layout.
      const int c = m.size[1], cells = m.size[2] * m.size[3];
      const float* p = m.ptr<float>();
      std::vector<float> t(static_cast<std::size_t>(c * cells));
      for (int k = 0; k < c; ++k)
        for (int j = 0; j < cells; ++j) t[static_cast<std::size_t>(j * c + k)] = p[k * cells + j];
      outputs.push_back(t);
    }
    ours[name] = outputs;
  }
  std::ofstream(out / "ours.json") << ours.dump() << "\n";
  std::printf("wrote %zu inputs and ours.json to %s\n", a.positional.size() - 1, out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s faces DIR | detect IMAGE... | chips OUT_DIR IMAGE... | objects IMAGE... | "
                 "object-outputs OUT_DIR IMAGE...\n",
                 argv[0]);
    return 2;
  }
  try {
    const Args a = parse(argc, argv);
    const std::string cmd = argv[1];
    if (cmd == "faces") return faces(a);
    if (cmd == "detect") return detect(a);
    if (cmd == "chips") return chips(a);
    if (cmd == "objects") return objects(a);
    if (cmd == "object-outputs") return object_outputs(a);
    std::fprintf(stderr, "unknown command %s\n", cmd.c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "marvin-vision-eval: %s\n", e.what());
    return 1;
  }
}
