// The people, devices and home pages' API against the real parts behind them: the face
// gallery in the SQLite file (as `marvin people` uses it), the smart home through a real
// mosquitto and the simulated home's devices (marvin-home-sim) with the host's HomeLink (as
// voice commands use it), and the example world's floor plan. Refusals name the field and
// change nothing.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <opencv2/imgcodecs.hpp>

#include "app/home_link.h"
#include "home_fixture.h"
#include "sim/world.h"
#include "vision/face_embedder.h"
#include "vision/face_gallery.h"
#include "web_client.h"
#include "web_site.h"

namespace marvin::web {
namespace {

using nlohmann::json;
using test::Browser;
using test::Reply;
using test::Site;
namespace fs = std::filesystem;

std::vector<float> face(float value) {
  return std::vector<float>(static_cast<std::size_t>(vision::kEmbeddingSize), value);
}

TEST_CASE("web: people are listed, renamed and forgotten through the face gallery") {
  Site site;
  vision::FaceGallery gallery(site.store);
  const std::int64_t anna = gallery.enroll("Anna", {face(0.1f), face(0.2f)}, "cli");
  const std::string markup = "<img src=x onerror=alert(1)>";
  gallery.enroll(markup, {face(0.9f)}, "voice:owner");
  Browser b = site.logged_in();

  Reply listed = b.send("GET", "/api/people");
  REQUIRE(listed.status == 200);
  REQUIRE(listed.json().size() == 2);
  CHECK(listed.json()[0]["name"] == markup);  // as data; the page shows it with textContent
  CHECK(listed.json()[1]["name"] == "Anna");
  CHECK(listed.json()[1]["faces"] == 2);
  CHECK(listed.json()[1]["enrolled_by"] == "cli");

  auto live = b.open_live();
  REQUIRE(live->next_event().first == "hello");
  const std::string path = "/api/people/" + std::to_string(anna);
  Reply renamed = b.send("PUT", path, json{{"name", "Anna Schmidt"}}.dump());
  REQUIRE(renamed.status == 200);
  CHECK(gallery.find("Anna Schmidt")->id == anna);
  CHECK(site.store.face_embeddings(anna).size() == 2);  // the faces stay
  // Open pages are told to reload people, and get the gallery's event (saying who did it).
  CHECK(live->next_event() ==
        std::pair<std::string, std::string>{"changed", R"({"what":"people"})"});
  auto event = live->next_event();
  CHECK(event.first == "event");
  CHECK(json::parse(event.second)["kind"] == "face_renamed");
  CHECK(json::parse(event.second)["source"] == "web");
  CHECK(json::parse(event.second)["message"] == "Anna is now called Anna Schmidt");

  // Refusals name the field; nobody is renamed.
  Reply taken = b.send("PUT", path, json{{"name", markup}}.dump());
  CHECK(taken.status == 400);
  CHECK(taken.error() ==
        "field 'name': " + markup + " is already enrolled; forget or rename them first");
  Reply empty = b.send("PUT", path, json{{"name", ""}}.dump());
  CHECK(empty.status == 400);
  CHECK(empty.error() == "field 'name': empty; give the person's name");
  Reply number = b.send("PUT", path, json{{"name", 7}}.dump());
  CHECK(number.status == 400);
  CHECK(number.error() == "field 'name': expected the person's new name as a string");
  Reply nobody = b.send("PUT", "/api/people/999", json{{"name", "Bob"}}.dump());
  CHECK(nobody.status == 404);
  CHECK(nobody.error() == "no person with id 999 is enrolled");
  b.no_csrf = true;
  Reply no_csrf = b.send("DELETE", path);
  b.no_csrf = false;
  CHECK(no_csrf.status == 403);
  REQUIRE(site.store.list_people().size() == 2);
  CHECK(gallery.find("Anna Schmidt"));

  Reply forgotten = b.send("DELETE", path);
  REQUIRE(forgotten.status == 200);
  CHECK(forgotten.json()["name"] == "Anna Schmidt");
  CHECK_FALSE(gallery.find("Anna Schmidt"));
  CHECK(site.store.face_embeddings(anna).empty());
  CHECK(site.store.recent_events(1).front().kind == "face_forgotten");
  CHECK(b.send("DELETE", path).status == 404);
  CHECK(site.store.list_people().size() == 1);
}

TEST_CASE("web: a face is learnt from an uploaded photo, with the CLI's rule of one face") {
  const std::filesystem::path sample = MARVIN_WEB_TEST_PHOTO;
  REQUIRE_MESSAGE(std::filesystem::exists(sample), sample.string()
                                                       << " is missing: run scripts/setup");
  const cv::Mat group = cv::imread(sample.string());
  std::vector<unsigned char> alone, everyone;
  // Anna alone (the crop `marvin people enroll` is tested with), and the whole group.
  cv::imencode(".png", group(cv::Rect(250, 250, 550, 550)), alone);
  cv::imencode(".jpg", group, everyone);
  Site site;
  Browser b = site.logged_in();
  auto upload = [&](const std::string& query, const std::vector<unsigned char>& bytes) {
    return b.send("POST", "/api/people/enroll?" + query, std::string(bytes.begin(), bytes.end()),
                  {{"Content-Type", "application/octet-stream"}});
  };

  // Refused: nothing is stored.
  Reply several = upload("name=Bob&file=party.jpg", everyone);
  CHECK(several.status == 422);
  CHECK(several.error().rfind("photo party.jpg: ", 0) == 0);
  CHECK(several.error().find(" faces; give photos of Bob alone; nothing was enrolled") !=
        std::string::npos);
  Reply garbage = upload("name=Bob&file=x.jpg", {'n', 'o', 't', ' ', 'a', 'n', ' ', 'i'});
  CHECK(garbage.status == 400);
  CHECK(garbage.error() == "photo: not a JPEG or PNG image");
  Reply nameless = upload("file=anna.png", alone);
  CHECK(nameless.status == 400);
  CHECK(nameless.error() ==
        "name: missing; send /api/people/enroll?name=NAME with a photo of them");
  CHECK(site.store.list_people().empty());
  CHECK(site.store.face_embeddings().empty());

  Reply learnt = upload("name=Anna&file=anna.png", alone);
  REQUIRE(learnt.status == 201);
  CHECK(learnt.json()["name"] == "Anna");
  CHECK(learnt.json()["faces"] == 1);
  REQUIRE(upload("name=anna&file=anna2.png", alone).json()["faces"] == 2);  // same person
  const json people = b.send("GET", "/api/people").json();
  REQUIRE(people.size() == 1);
  CHECK(people[0]["enrolled_by"] == "web");
  // The face is the one the robot's camera would recognise.
  vision::FaceGallery gallery(site.store);
  CHECK(gallery.list().front().embeddings == 2);
}

TEST_CASE("web: the home map is the world's floor plan, the robot on it and what was seen") {
  const sim::World world = sim::load_world(MARVIN_HOME_WORLD);
  navigation::Pose pose = world.robot.start;
  std::mutex pose_mutex;
  Site site(1024 * 1024, [&](WebOptions& o) {
    o.floor_map = &world.map;
    o.robot_pose = [&]() -> std::optional<navigation::Pose> {
      std::lock_guard lock(pose_mutex);
      return pose;
    };
  });
  site.store.record_sighting({"keys", "object", "kitchen", "kitchen table", 0});
  Browser b = site.logged_in();
  json home = b.send("GET", "/api/home").json();
  REQUIRE(home["map"].is_object());
  CHECK(home["map"]["rooms"].size() == world.map.rooms.size());
  CHECK(home["map"]["walls"].size() == world.map.walls.size());
  CHECK(home["map"]["rooms"][0]["name"] == world.map.rooms[0].name);
  const navigation::Room* start_room = world.map.room_at(world.robot.start.position());
  REQUIRE(start_room);
  CHECK(home["robot"]["room"] == start_room->name);
  REQUIRE(home["sightings"].size() == 1);
  CHECK(home["sightings"][0]["what"] == "keys");
  CHECK(home["sightings"][0]["near"] == "kitchen table");

  // The robot drove to the kitchen: the map says so at the next look.
  {
    std::lock_guard lock(pose_mutex);
    pose = {8.0, 3.0, 0};
  }
  home = b.send("GET", "/api/home").json();
  CHECK(home["robot"]["room"] == "kitchen");
  CHECK(home["robot"]["at"] == json::array({8.0, 3.0}));
}

TEST_CASE("web: without a robot the home and devices pages say so, and switching is refused") {
  Site site;
  Browser b = site.logged_in();
  json home = b.send("GET", "/api/home").json();
  CHECK(home["map"].is_null());
  CHECK(home["robot"].is_null());
  json devices = b.send("GET", "/api/devices").json();
  CHECK(devices["configured"] == false);
  CHECK(devices["devices"].empty());
  Reply set = b.send("POST", "/api/devices/lamp", json{{"on", true}}.dump());
  CHECK(set.status == 503);
  CHECK(set.error().rfind("no smart home here", 0) == 0);
}

TEST_CASE("web: devices are listed and switched through the home's broker, as by voice") {
  using namespace home::testing;
  MosquittoBroker broker;
  ChildProcess sim = start_sim(broker);
  home::HomeService service(config_for(broker));
  service.start();
  REQUIRE(service.wait_connected(kWait));
  REQUIRE(service.wait_devices(
      [](const std::vector<home::Device>& ds) {
        for (const home::Device& d : ds)
          if (d.name == "living room lamp" && d.state.on.has_value()) return true;
        return false;
      },
      kWait));
  app::HomeLink link(service);
  Site site(1024 * 1024, [&](WebOptions& o) { o.smart_home = &link; });
  Browser b = site.logged_in();

  json listed = b.send("GET", "/api/devices").json();
  CHECK(listed["configured"] == true);
  CHECK(listed["connected"] == true);
  json lamp;
  for (const json& d : listed["devices"])
    if (d["name"] == "living room lamp") lamp = d;
  REQUIRE(lamp.is_object());
  CHECK(lamp["room"] == "living room");
  CHECK(lamp["on"] == false);
  // The id as the page sends it (encodeURIComponent): "z2m:living room/living room lamp".
  std::string encoded;
  for (const char c : lamp["id"].get<std::string>()) {
    if (c == ' ')
      encoded += "%20";
    else if (c == '/')
      encoded += "%2F";
    else
      encoded += c;
  }
  const std::string path = "/api/devices/" + encoded;

  // Bad input names the field; the lamp is not touched.
  Reply not_bool = b.send("POST", path, json{{"on", "yes"}}.dump());
  CHECK(not_bool.status == 400);
  CHECK(not_bool.error() == "field 'on': expected true or false");
  Reply too_bright = b.send("POST", path, json{{"on", true}, {"brightness", 150}}.dump());
  CHECK(too_bright.status == 400);
  CHECK(too_bright.error() == "field 'brightness': expected a whole number 0..100 (percent)");
  Reply nothing = b.send("POST", path, "{}");
  CHECK(nothing.status == 400);
  CHECK(nothing.error() == "field 'on': missing (or give 'brightness' or 'target_temperature')");
  Reply unknown = b.send("POST", "/api/devices/the%20moon", json{{"on", true}}.dump());
  CHECK(unknown.status == 404);
  CHECK(unknown.error() == "there is no device \"the moon\"");
  Reply fan_dim = b.send("POST", "/api/devices/bedroom%20fan", json{{"brightness", 20}}.dump());
  CHECK(fan_dim.status == 400);
  CHECK(fan_dim.error() == "the bedroom fan cannot be dimmed");
  Reply not_degrees = b.send("POST", "/api/devices/living%20room%20thermostat",
                             json{{"target_temperature", "warm"}}.dump());
  CHECK(not_degrees.status == 400);
  CHECK(not_degrees.error() == "field 'target_temperature': expected degrees Celsius (a number)");
  Reply too_hot = b.send("POST", "/api/devices/living%20room%20thermostat",
                         json{{"target_temperature", 35}}.dump());
  CHECK(too_hot.status == 400);
  CHECK(too_hot.error() == "the living room thermostat can be set from 5 to 30 degrees");
  Reply lamp_heat = b.send("POST", path, json{{"target_temperature", 21}}.dump());
  CHECK(lamp_heat.status == 400);
  CHECK(lamp_heat.error() == "the living room lamp is not a thermostat");
  for (const home::Device& d : service.devices()) {
    if (d.name == "living room lamp") CHECK(d.state.on == false);
    if (d.name == "living room thermostat") CHECK(d.state.target_c == 20.0);
  }
  // A set point in range: answered with what the thermostat reported.
  Reply warmer = b.send("POST", "/api/devices/living%20room%20thermostat",
                        json{{"target_temperature", 21.5}}.dump());
  REQUIRE(warmer.status == 200);
  CHECK(warmer.json()["target_temperature"] == 21.5);
  CHECK(warmer.json()["temperature"] == 19.5);

  // Switched on: the answer is the state the lamp reported back.
  Reply on = b.send("POST", path, json{{"on", true}}.dump());
  REQUIRE(on.status == 200);
  CHECK(on.json()["on"] == true);
  const json after = b.send("GET", "/api/devices").json();
  for (const json& d : after["devices"])
    if (d["name"] == "living room lamp") CHECK(d["on"] == true);
  Reply off = b.send("POST", path, json{{"on", false}}.dump());
  REQUIRE(off.status == 200);
  CHECK(off.json()["on"] == false);

  // Dimmed as the page's brightness input sends it: the answer is the reported brightness.
  Reply dim = b.send("POST", "/api/devices/kitchen%20light",
                     json{{"on", true}, {"brightness", 30}}.dump());
  REQUIRE(dim.status == 200);
  CHECK(dim.json()["on"] == true);
  CHECK(dim.json()["brightness"] == 30);
  CHECK(dim.json()["dimmable"] == true);

  // Switched by voice (the host's HomeLink, not the page): an open page is told to reload
  // its devices once the lamp reported the new state, and then reads it on.
  auto live = b.open_live();
  REQUIRE(live->next_event().first == "hello");
  REQUIRE(link.set(lamp["id"].get<std::string>(), json{{"on", true}}).result ==
          skills::SmartHome::Result::kDone);
  auto changed = live->next_event();
  CHECK(changed.first == "changed");
  CHECK(json::parse(changed.second) == json{{"what", "devices"}});
  const json now_listed = b.send("GET", "/api/devices").json();  // outlives the loop over it
  int lamps_on = 0;
  for (const json& d : now_listed["devices"])
    if (d["name"] == "living room lamp" && d["on"] == true) ++lamps_on;
  CHECK(lamps_on == 1);
  service.stop();
}

// An intruder alert as the guard logs it (app/host.cpp), naming `photo`; its event id.
std::int64_t log_intruder(data::SqliteStore& store, const std::string& photo,
                          const std::string& kind = "intruder") {
  store.log_event(kind, "guard", "Intruder alert: I see someone I don't know. Photo: " + photo);
  return store.recent_events(1).at(0).id;
}

std::string jpeg_bytes(int value) {
  std::vector<unsigned char> out;
  REQUIRE(cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(value, value, value)), out));
  return std::string(out.begin(), out.end());
}

std::string photo_path(std::int64_t id) { return "/api/events/" + std::to_string(id) + "/photo"; }

TEST_CASE("web: an intruder photo is served by event id, only from the photo folder") {
  Site site;
  const fs::path folder = site.tmp / "data/photos/guard";
  fs::create_directories(folder);
  const std::string photo = jpeg_bytes(200);
  test_support::write_text(folder / "photo-1.jpg", photo);
  // Outside the folder: a JPEG, and a secret the events point at in several ways.
  const std::string secret = jpeg_bytes(7) + "SECRET-BYTES";
  test_support::write_text(site.tmp / "data/secret.jpg", secret);
  fs::create_symlink(site.tmp / "data/secret.jpg", folder / "link.jpg");
  fs::create_directory_symlink(site.tmp / "data", folder / "outside");
  test_support::write_text(folder / "notes.jpg", "not a photo at all");
  REQUIRE(::mkfifo((folder / "pipe.jpg").c_str(), 0600) == 0);  // must not block the server

  const std::int64_t good = log_intruder(site.store, (folder / "photo-1.jpg").string());
  Browser b = site.logged_in();

  SUBCASE("the page's session gets the photo as image/jpeg, and the event says it has one") {
    Reply r = b.send("GET", photo_path(good));
    CHECK(r.status == 200);
    CHECK(r.content_type == "image/jpeg");
    CHECK(r.body == photo);
    const json events = b.send("GET", "/api/events").json();
    REQUIRE(!events.empty());
    CHECK(events[0]["id"] == good);
    CHECK(events[0]["photo"] == true);
  }
  SUBCASE("without a session nothing is served") {
    Reply r = site.browser().send("GET", photo_path(good));
    CHECK(r.status == 401);
    CHECK(r.error() == "not logged in, or the session expired: log in at /login.html");
    CHECK(r.body.find(photo.substr(0, 64)) == std::string::npos);
  }
  SUBCASE("an event whose photo lies outside the folder is refused, naming neither path nor bytes") {
    for (const std::string& named :
         {(site.tmp / "data/secret.jpg").string(), (folder / "../../secret.jpg").string(),
          (folder / "link.jpg").string(), (folder / "outside/secret.jpg").string(),
          (folder / "notes.jpg").string(), (folder / "pipe.jpg").string()}) {
      CAPTURE(named);
      const std::int64_t id = log_intruder(site.store, named);
      Reply r = b.send("GET", photo_path(id));
      CHECK(r.status == 403);
      CHECK(r.error() == "event " + std::to_string(id) +
                             ": its photo is not in Marvin's photo folder; nothing is served");
      CHECK(r.body.find("SECRET") == std::string::npos);
      CHECK(r.body.find((site.tmp / "data").string()) == std::string::npos);
      CHECK(r.content_type.rfind("application/json", 0) == 0);
    }
  }
  SUBCASE("only an intruder alert names a photo; unknown ids and bad ids are refused") {
    const std::int64_t other = log_intruder(site.store, (folder / "photo-1.jpg").string(), "skill");
    Reply not_alert = b.send("GET", photo_path(other));
    CHECK(not_alert.status == 404);
    CHECK(not_alert.error() == "event " + std::to_string(other) + " has no photo");
    CHECK(b.send("GET", "/api/events").json()[0]["photo"] == false);
    Reply unknown = b.send("GET", photo_path(other + 100));
    CHECK(unknown.status == 404);
    CHECK(unknown.error() == "no event with id " + std::to_string(other + 100));
    Reply bad = b.send("GET", "/api/events/..%2Fsecret.jpg/photo");
    CHECK(bad.status == 404);
    CHECK(bad.error() == "event id '../secret.jpg' is not a number");
  }
  // Nothing stored changed: the photos are where they were, byte for byte.
  CHECK(test_support::read_text(folder / "photo-1.jpg") == photo);
  CHECK(test_support::read_text(site.tmp / "data/secret.jpg") == secret);
}

}  // namespace
}  // namespace marvin::web
