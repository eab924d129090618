#include "vision/object_memory.h"

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace marvin::vision {
namespace {

constexpr const char* kOwner = "marvin.vision.objects";
constexpr char kObjectMagic[8] = {'M', 'V', 'O', 'B', 'J', 'E', 'C', '1'};

const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64(const std::string& in) {
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) |
                       (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    for (int k = 18; k >= 0; k -= 6) out += kAlphabet[(v >> k) & 63];
  }
  if (i < in.size()) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < in.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string unbase64(const std::string& in) {
  std::string out;
  unsigned v = 0;
  int bits = 0;
  for (char c : in) {
    const char* p = std::strchr(kAlphabet, c);
    if (c == '=' || p == nullptr || c == '\0') continue;
    v = (v << 6) | static_cast<unsigned>(p - kAlphabet);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((v >> bits) & 0xFF);
    }
  }
  return out;
}

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename T>
T take(const std::string& in, std::size_t& pos, const std::string& name) {
  if (in.size() - pos < sizeof(T)) {
    throw std::runtime_error("taught object " + name + ": stored record truncated at byte " +
                             std::to_string(pos));
  }
  T v;
  std::memcpy(&v, in.data() + pos, sizeof v);
  pos += sizeof v;
  return v;
}

}  // namespace

ObjectMemory::ObjectMemory(data::PersonalData& store)
    : store_(store), orb_(cv::ORB::create(1000)) {}

void ObjectMemory::features(const cv::Mat& image_bgr, std::vector<cv::KeyPoint>& keypoints,
                            cv::Mat& descriptors) {
  cv::Mat grey;
  cv::cvtColor(image_bgr, grey, cv::COLOR_BGR2GRAY);
  orb_->detectAndCompute(grey, cv::noArray(), keypoints, descriptors);
}

std::vector<std::string> ObjectMemory::names() {
  const auto text = store_.storage_get(kOwner, "names");
  if (!text) return {};
  return nlohmann::json::parse(*text).get<std::vector<std::string>>();
}

void ObjectMemory::save_names(const std::vector<std::string>& names) {
  store_.storage_set(kOwner, "names", nlohmann::json(names).dump());
}

void ObjectMemory::teach(const std::string& name, const cv::Mat& image_bgr, cv::Rect region) {
  if (name.empty()) throw std::invalid_argument("name: an object to learn needs a name");
  const cv::Rect whole(0, 0, image_bgr.cols, image_bgr.rows);
  if (region.area() == 0) {
    region = cv::Rect(image_bgr.cols / 4, image_bgr.rows / 4, image_bgr.cols / 2, image_bgr.rows / 2);
  }
  if ((region & whole) != region || region.area() == 0) {
    throw std::invalid_argument("the region shown for " + name + " is outside the picture");
  }
  Look look;
  look.size = region.size();
  features(image_bgr(region), look.keypoints, look.descriptors);
  if (static_cast<int>(look.keypoints.size()) < kMinFeatures) {
    throw std::invalid_argument(name + " looks too plain to recognise (" +
                                std::to_string(look.keypoints.size()) + " features, need " +
                                std::to_string(kMinFeatures) + "); show it closer or on a plain background");
  }
  std::string rec(kObjectMagic, 8);
  put<int32_t>(rec, look.size.width);
  put<int32_t>(rec, look.size.height);
  put<int32_t>(rec, static_cast<int32_t>(look.keypoints.size()));
  for (const auto& k : look.keypoints) {
    put<float>(rec, k.pt.x);
    put<float>(rec, k.pt.y);
    put<float>(rec, k.size);
    put<float>(rec, k.angle);
  }
  rec.append(reinterpret_cast<const char*>(look.descriptors.data),
             look.descriptors.total() * look.descriptors.elemSize());
  store_.storage_set(kOwner, "object:" + name, base64(rec));
  auto all = names();
  if (std::find(all.begin(), all.end(), name) == all.end()) {
    all.push_back(name);
    save_names(all);
  }
}

bool ObjectMemory::forget(const std::string& name) {
  auto all = names();
  auto it = std::find(all.begin(), all.end(), name);
  if (it == all.end()) return false;
  all.erase(it);
  store_.storage_remove(kOwner, "object:" + name);
  save_names(all);
  return true;
}

std::optional<ObjectMemory::Look> ObjectMemory::load(const std::string& name) {
  const auto text = store_.storage_get(kOwner, "object:" + name);
  if (!text) return std::nullopt;
  const std::string rec = unbase64(*text);
  if (rec.size() < 8 || std::memcmp(rec.data(), kObjectMagic, 8) != 0) {
    throw std::runtime_error("taught object " + name + ": stored record is not an MVOBJEC1 record");
  }
  std::size_t pos = 8;
  Look look;
  look.size.width = take<int32_t>(rec, pos, name);
  look.size.height = take<int32_t>(rec, pos, name);
  const int32_t n = take<int32_t>(rec, pos, name);
  if (n <= 0 || n > 100000) {
    throw std::runtime_error("taught object " + name + ": " + std::to_string(n) +
                             " features in the stored record, expected 1 to 100000");
  }
  for (int32_t i = 0; i < n; ++i) {
    cv::KeyPoint k;
    k.pt.x = take<float>(rec, pos, name);
    k.pt.y = take<float>(rec, pos, name);
    k.size = take<float>(rec, pos, name);
    k.angle = take<float>(rec, pos, name);
    look.keypoints.push_back(k);
  }
  if (rec.size() - pos != static_cast<std::size_t>(n) * 32) {
    throw std::runtime_error("taught object " + name + ": " + std::to_string(rec.size() - pos) +
                             " descriptor bytes, expected " + std::to_string(n * 32));
  }
  look.descriptors = cv::Mat(n, 32, CV_8U);
  std::memcpy(look.descriptors.data, rec.data() + pos, rec.size() - pos);
  return look;
}

std::optional<ObjectSighting> ObjectMemory::match(const std::string& name, const Look& look,
                                                  const std::vector<cv::KeyPoint>& keypoints,
                                                  const cv::Mat& descriptors) {
  if (descriptors.empty() || keypoints.size() < 4) return std::nullopt;
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(look.descriptors, descriptors, knn, 2);
  std::vector<cv::Point2f> from, to;
  for (const auto& m : knn) {
    if (m.size() == 2 && m[0].distance < 0.75f * m[1].distance) {
      from.push_back(look.keypoints[static_cast<std::size_t>(m[0].queryIdx)].pt);
      to.push_back(keypoints[static_cast<std::size_t>(m[0].trainIdx)].pt);
    }
  }
  if (static_cast<int>(from.size()) < kMinInliers) return std::nullopt;
  std::vector<unsigned char> inlier_mask;
  const cv::Mat h = cv::findHomography(from, to, cv::RANSAC, 5.0, inlier_mask);
  if (h.empty()) return std::nullopt;
  const int inliers = cv::countNonZero(inlier_mask);
  if (inliers < kMinInliers) return std::nullopt;
  const auto w = static_cast<float>(look.size.width), hgt = static_cast<float>(look.size.height);
  std::vector<cv::Point2f> corners = {{0, 0}, {w, 0}, {w, hgt}, {0, hgt}}, outline;
  cv::perspectiveTransform(corners, outline, h);
  if (!cv::isContourConvex(outline) || cv::contourArea(outline) < 0.01 * w * hgt) return std::nullopt;
  ObjectSighting s;
  s.name = name;
  s.outline = outline;
  s.box = cv::boundingRect(outline);
  s.inliers = inliers;
  return s;
}

std::optional<ObjectSighting> ObjectMemory::find(const std::string& name, const cv::Mat& image_bgr) {
  const auto look = load(name);
  if (!look) throw std::invalid_argument("no object called " + name + " was taught");
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  features(image_bgr, keypoints, descriptors);
  return match(name, *look, keypoints, descriptors);
}

std::vector<ObjectSighting> ObjectMemory::find_all(const cv::Mat& image_bgr) {
  std::vector<ObjectSighting> out;
  const auto all = names();
  if (all.empty()) return out;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  features(image_bgr, keypoints, descriptors);
  for (const auto& name : all) {
    if (auto look = load(name)) {
      if (auto s = match(name, *look, keypoints, descriptors)) out.push_back(std::move(*s));
    }
  }
  return out;
}

}  // namespace marvin::vision
