// The JSON API's operations (API.md), apart from the transport: login, sessions, CSRF and
// live updates are the server's (web_server.cpp). Each operation calls the same core
// function as the CLI: data::parse_repeat and local_to_utc_ms for reminders, the store's
// add/list/remove, store::Installer for skills, vision::FaceGallery for people, the host's
// smart home (skills::SmartHome, as voice and skills use it) for devices.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "web/web_server.h"

namespace marvin::vision {
class FacePipeline;
}  // namespace marvin::vision

namespace marvin::web {

struct ApiRequest {
  std::string method;  // GET, POST, PUT, DELETE
  std::string path;    // /api/reminders/3
  std::map<std::string, std::string> query;
  std::string body;
  std::string signature;  // a skill upload's .minisig text (X-Marvin-Signature, base64)
};

struct ApiResponse {
  ApiResponse() = default;
  ApiResponse(unsigned s, nlohmann::json b) : status(s), body(std::move(b)) {}
  unsigned status = 200;
  nlohmann::json body;  // {"error": "..."} when status >= 400
  // Not JSON (an event's photo): sent as these bytes with this content type instead of body.
  std::string content_type;
  std::string raw;
};

class Api {
 public:
  Api(const WebOptions& options, data::PersonalData& data, data::SqliteStore& store, LiveFeed* feed)
      : options_(options), data_(data), store_(store), feed_(feed) {}
  ~Api();

  ApiResponse handle(const ApiRequest& request);

  // One event as the API shows it (also sent live).
  nlohmann::json event_json(std::int64_t id, std::int64_t time_utc_ms, const std::string& kind,
                            const std::string& source, const std::string& message) const;

 private:
  ApiResponse status();
  ApiResponse reminders(const ApiRequest& r, const std::string& id);
  ApiResponse contacts(const ApiRequest& r, const std::string& id);
  ApiResponse skills(const ApiRequest& r, const std::string& id, const std::string& action);
  ApiResponse install_skill(const ApiRequest& r);
  ApiResponse events(const ApiRequest& r);
  // api_home.cpp: the people Marvin knows by face, smart-home devices, the home map.
  ApiResponse people(const ApiRequest& r, const std::string& id);
  ApiResponse enroll_person(const ApiRequest& r);
  ApiResponse devices(const ApiRequest& r, const std::string& id);
  ApiResponse home();
  // api_photos.cpp: an intruder event's photo, by the event's id.
  ApiResponse event_photo(const std::string& id);
  std::filesystem::path photos_dir() const;

  const WebOptions& options_;
  data::PersonalData& data_;
  data::SqliteStore& store_;
  LiveFeed* feed_;
  std::unique_ptr<vision::FacePipeline> faces_;  // the face models, loaded at the first enrolment
};

// A refusal with its HTTP status; Api::handle() answers {"error": message}.
struct ApiError : std::runtime_error {
  ApiError(unsigned s, const std::string& message) : std::runtime_error(message), status(s) {}
  unsigned status;
};

// The photo an event names ("... Photo: <path>" at the end of an intruder alert), or "".
std::string photo_of_event(const std::string& kind, const std::string& message);

// The request's JSON object (400 naming the body otherwise), and an id in a path.
nlohmann::json parse_body(const std::string& body);
std::int64_t parse_id(const std::string& text, const char* what);

// "a%20b" -> "a b"; throws std::runtime_error on a bad escape.
std::string url_decode(std::string_view text);

}  // namespace marvin::web
