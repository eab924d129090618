// vision_bench: one core (OpenCV's thread pool set to 1), a 640x480 frame made from face-api's
// demo photo (fetched by scripts/setup) with three faces. Prints frames per second for
//   - BlazeFace (back, 256) detection alone,
//   - detection + the 128-number embedding of one face (the goal: >= 10 frames/s),
//   - detection + embeddings of every face found,
//   - the Haar cascade (the original robot's detector), timed in the same run: the ratio is
//     the figure to quote,
//   - COCO object detection (NanoDet 416, the goal: >= 5 frames/s) on the same frame,
//     and the face pipeline plus object detection together (what vision_look does),
// and the memory of the loaded models (weights held, and the process's resident memory
// growth while loading). Never fails on time.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "vision/cameras.h"
#include "vision/face_detector.h"
#include "vision/face_embedder.h"
#include "vision/model_files.h"
#include "vision/object_detector.h"

using namespace marvin::vision;

namespace {

long resident_kib() {
  std::ifstream in("/proc/self/statm");
  long pages = 0, resident = 0;
  in >> pages >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

// Frames per second of `step` over at least `seconds` (after two warm-up runs).
double fps(const std::function<void()>& step, double seconds = 2.0) {
  step();
  step();
  int n = 0;
  const auto start = std::chrono::steady_clock::now();
  double elapsed = 0;
  while (elapsed < seconds) {
    step();
    ++n;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return n / elapsed;
}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  const char* src = std::getenv("MARVIN_SOURCE_DIR");
  const std::filesystem::path photo =
      argc > 1 ? std::filesystem::path(argv[1])
               : std::filesystem::path(src ? src : ".") / ".cache/vision/photos/sample1.jpg";
  try {
    // 640x480: the photo scaled to 640 wide (427 rows), centred on black.
    const cv::Mat original = read_photo(photo);
    cv::Mat scaled;
    cv::resize(original, scaled, cv::Size(640, 640 * original.rows / original.cols), 0, 0,
               cv::INTER_AREA);
    cv::Mat frame(480, 640, CV_8UC3, cv::Scalar());
    scaled.copyTo(frame(cv::Rect(0, (480 - scaled.rows) / 2, 640, scaled.rows)));

    const long before = resident_kib();
    BlazeFaceDetector blaze;
    const long after_detector = resident_kib();
    FaceEmbedder embedder;
    embedder.embed_chip(cv::Mat(150, 150, CV_8UC3, cv::Scalar()));  // allocates its buffers
    const long after_embedder = resident_kib();
    HaarFaceDetector haar;
    const long after_haar = resident_kib();
    ObjectDetector objects;
    objects.detect(frame);  // allocates its buffers
    const long after_objects = resident_kib();

    const auto faces = blaze.detect(frame);
    if (faces.empty()) {
      std::printf("no face found in %s: cannot time the embedding\n", photo.c_str());
      return 1;
    }
    std::printf("vision_bench: 640x480 frame from %s, %zu faces, 1 thread\n\n", photo.c_str(),
                faces.size());
    const double detect_fps = fps([&] { blaze.detect(frame); });
    const double one_fps = fps([&] {
      const auto f = blaze.detect(frame);
      embedder.embed_chip(face_chip(frame, f.front()));
    });
    const double all_fps = fps([&] {
      for (const auto& f : blaze.detect(frame)) embedder.embed_chip(face_chip(frame, f));
    });
    const cv::Mat chip = face_chip(frame, faces.front());
    const double embed_fps = fps([&] { embedder.embed_chip(chip); });
    const double haar_fps = fps([&] { haar.detect(frame); });
    const double objects_fps = fps([&] { objects.detect(frame); });
    const double look_fps = fps([&] {
      for (const auto& f : blaze.detect(frame)) embedder.embed_chip(face_chip(frame, f));
      objects.detect(frame);
    });
    const auto found = objects.detect(frame);

    std::printf("BlazeFace (back, 256) detection          %7.1f frames/s\n", detect_fps);
    std::printf("face embedding (one 150x150 chip)        %7.1f faces/s\n", embed_fps);
    std::printf("detection + embedding of one face        %7.1f frames/s  (goal >= 10)\n", one_fps);
    std::printf("detection + embedding of all %zu faces    %7.1f frames/s\n", faces.size(), all_fps);
    std::printf("Haar cascade detection (baseline)        %7.1f frames/s\n", haar_fps);
    std::printf("BlazeFace / Haar detection speed         %7.2fx\n", detect_fps / haar_fps);
    std::printf("object detection (NanoDet 416, COCO)     %7.1f frames/s  (goal >= 5; %zu objects)\n",
                objects_fps, found.size());
    std::printf("faces (all) + objects, as vision_look    %7.1f frames/s\n\n", look_fps);
    std::printf("memory: embedder weights %.1f MB, object detector weights %.1f MB; resident "
                "growth while loading: BlazeFace %.1f MB, embedder %.1f MB, Haar %.1f MB, "
                "object detector %.1f MB\n",
                static_cast<double>(embedder.weight_bytes()) / 1e6,
                static_cast<double>(objects.weight_bytes()) / 1e6,
                static_cast<double>(after_detector - before) / 1024.0,
                static_cast<double>(after_embedder - after_detector) / 1024.0,
                static_cast<double>(after_haar - after_embedder) / 1024.0,
                static_cast<double>(after_objects - after_haar) / 1024.0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vision_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
