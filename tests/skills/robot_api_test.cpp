// The host's Robot API table: permissions, the JSON formats, buffers, unavailable
// capabilities. Bad calls change nothing.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "skills/host_api.h"
#include "skills/in_memory_personal_data.h"

using namespace marvin::skills;
using nlohmann::json;

namespace {

struct RecordingBody : marvin::devices::Body {
  std::vector<std::string> actions;
  void move(marvin::devices::Direction d, std::uint8_t speed,
            std::chrono::milliseconds ms) override {
    actions.push_back("move " + std::to_string(static_cast<int>(d)) + " " + std::to_string(speed) +
                      " " + std::to_string(ms.count()));
  }
  void stop() override { actions.push_back("stop"); }
  void tilt_head(int degrees) override { actions.push_back("tilt " + std::to_string(degrees)); }
  std::vector<marvin::devices::ScanPoint> latest_scan() override {
    return {{0, 1.5, 0}, {90, 2.5, 0}};
  }
  void set_light(marvin::devices::Light l) override {
    actions.push_back("light " + std::to_string(static_cast<int>(l)));
  }
};

struct World {
  InMemoryPersonalData data;
  RecordingBody body;
  HostServices services;
  World() {
    services.data = &data;
    services.body = &body;
    services.time_zone = "Europe/Berlin";
    services.now_ms = [] { return 1767603600000; };  // 2026-01-05T09:00Z
    services.wait_for_motion = false;
  }
};

const marvin_robot_api& api() { return *host_robot_api(); }

std::string call_text(marvin_host* host, marvin_status (*fn)(marvin_host*, marvin_text_out*),
                      marvin_status* status) {
  char buffer[4096];
  marvin_text_out out{buffer, sizeof buffer, 0};
  *status = fn(host, &out);
  return std::string(buffer, *status == MARVIN_OK ? out.length : 0);
}

}  // namespace

TEST_CASE("the table says its size and version") {
  CHECK(api().struct_size == sizeof(marvin_robot_api));
  CHECK(api().major == MARVIN_ROBOT_API_MAJOR);
  CHECK(api().minor == MARVIN_ROBOT_API_MINOR);
}

TEST_CASE("calls without the permission fail with a clear error and do nothing") {
  World w;
  SkillContext c("dice", {"storage"}, w.services);
  CHECK(api().move(c.host(), MARVIN_FORWARD, 100, 1000) == MARVIN_ERR_PERMISSION);
  CHECK(std::string(api().last_error(c.host())) ==
        "permission 'motion' is not granted to skill 'dice'");
  CHECK(api().set_light(c.host(), MARVIN_LIGHT_EXECUTING) == MARVIN_ERR_PERMISSION);
  CHECK(std::string(api().last_error(c.host())) ==
        "permission 'light' is not granted to skill 'dice'");
  CHECK(api().schedule_add(c.host(), R"({"title":"pills","at":"2026-01-05T20:00"})", nullptr) ==
        MARVIN_ERR_PERMISSION);
  CHECK(w.body.actions.empty());
  CHECK(w.data.list_reminders().empty());
  // A successful call clears the error.
  CHECK(api().storage_set(c.host(), "k", "v", 1) == MARVIN_OK);
  CHECK(std::string(api().last_error(c.host())).empty());
}

TEST_CASE("body calls reach the body; bad arguments are refused") {
  World w;
  SkillContext c("walker", {"motion", "light", "sensors"}, w.services);
  CHECK(api().move(c.host(), MARVIN_TURN_LEFT, 120, 1500) == MARVIN_OK);
  CHECK(api().tilt_head(c.host(), 20) == MARVIN_OK);
  CHECK(api().set_light(c.host(), MARVIN_LIGHT_LISTENING) == MARVIN_OK);
  CHECK(api().tilt_head(c.host(), 75) == MARVIN_ERR_INVALID);
  CHECK(std::string(api().last_error(c.host())) == "the head tilts from -60 to 60 degrees, got 75");
  CHECK(w.body.actions == std::vector<std::string>{"move 2 120 1500", "tilt 20", "light 2"});

  marvin_scan_point points[1];
  size_t count = 0;
  CHECK(api().obstacle_scan(c.host(), points, 1, &count) == MARVIN_ERR_TRUNCATED);
  CHECK(count == 1);
  CHECK(points[0].distance_m == 1.5);

  c.cancel();
  CHECK(api().is_cancelled(c.host()) == 1);
  CHECK(api().move(c.host(), MARVIN_FORWARD, 100, 1000) == MARVIN_ERR_CANCELLED);
  c.begin_request();
  CHECK(api().is_cancelled(c.host()) == 0);
}

TEST_CASE("schedules: the README's JSON in and out, stored once acknowledged") {
  World w;
  SkillContext c("reminders", {"schedule"}, w.services);
  char buffer[1024];
  marvin_text_out out{buffer, sizeof buffer, 0};
  REQUIRE(api().schedule_add(c.host(),
                             R"({"title":"take my pills","at":"2026-01-05T20:00",
                                 "recurrence":{"kind":"daily"}})",
                             &out) == MARVIN_OK);
  json created = json::parse(std::string(buffer, out.length));
  CHECK(created["title"] == "take my pills");
  CHECK(created["at"] == "2026-01-05T20:00");
  CHECK(created["time_zone"] == "Europe/Berlin");
  CHECK(created["recurrence"]["kind"] == "daily");
  CHECK(created["created_by"] == "reminders");
  CHECK(created["next_fire_utc_ms"] == 1767639600000);  // 19:00 UTC
  REQUIRE(w.data.list_reminders().size() == 1);
  CHECK(w.data.list_reminders()[0].id == created["id"].get<std::int64_t>());

  out = {buffer, sizeof buffer, 0};
  REQUIRE(api().schedule_list(c.host(), 1767639600000, 1767639600001, &out) == MARVIN_OK);
  CHECK(json::parse(std::string(buffer, out.length)).size() == 1);

  // Bad input: a clear message and nothing stored.
  CHECK(api().schedule_add(c.host(), R"({"title":"x","at":"tomorrow"})", nullptr) ==
        MARVIN_ERR_INVALID);
  CHECK(std::string(api().last_error(c.host())) ==
        "reminder_json: \"at\": expected local time \"YYYY-MM-DDTHH:MM\", got \"tomorrow\"");
  CHECK(api().schedule_add(c.host(), R"({"title":"x","at":"2026-01-05T20:00",
                                         "recurrence":{"kind":"weekly"}})",
                           nullptr) == MARVIN_ERR_INVALID);
  CHECK(std::string(api().last_error(c.host())) ==
        "reminder_json: \"recurrence.weekdays\": a weekly reminder needs at least one day");
  CHECK(api().schedule_add(c.host(), R"({"title":"x","at":"2026-01-05T20:00",
                                         "utc_ms":1767639660000})",
                           nullptr) == MARVIN_ERR_INVALID);  // 19:01 UTC: the next minute
  CHECK(std::string(api().last_error(c.host())) ==
        "reminder_json: \"utc_ms\": must lie in the minute \"at\" names");
  CHECK(api().schedule_add(c.host(), "{not json", nullptr) == MARVIN_ERR_INVALID);
  CHECK(
      std::string(api().last_error(c.host())).rfind("reminder_json is not valid JSON at byte", 0) ==
      0);
  CHECK(w.data.list_reminders().size() == 1);

  // To the second: a timer's exact instant inside the minute "at" names.
  out = {buffer, sizeof buffer, 0};
  REQUIRE(api().schedule_add(c.host(), R"({"title":"timer","at":"2026-01-05T20:00",
                                           "utc_ms":1767639630500})",
                             &out) == MARVIN_OK);
  CHECK(json::parse(std::string(buffer, out.length))["next_fire_utc_ms"] == 1767639630500);
  CHECK(api().schedule_remove(c.host(),
                              json::parse(std::string(buffer, out.length))["id"].get<std::int64_t>()) ==
        MARVIN_OK);

  CHECK(api().schedule_remove(c.host(), created["id"].get<std::int64_t>()) == MARVIN_OK);
  CHECK(api().schedule_remove(c.host(), created["id"].get<std::int64_t>()) == MARVIN_ERR_NOT_FOUND);
  CHECK(w.data.list_reminders().empty());
}

TEST_CASE("a local time in the spring gap is moved to the end of the gap") {
  World w;
  SkillContext c("reminders", {"schedule"}, w.services);
  char buffer[1024];
  marvin_text_out out{buffer, sizeof buffer, 0};
  REQUIRE(api().schedule_add(c.host(), R"({"title":"x","at":"2026-03-29T02:30"})", &out) ==
          MARVIN_OK);
  CHECK(json::parse(std::string(buffer, out.length))["at"] == "2026-03-29T03:00");
}

TEST_CASE("contacts and people") {
  World w;
  SkillContext c("phone", {"contacts"}, w.services);
  char buffer[1024];
  marvin_text_out out{buffer, sizeof buffer, 0};
  REQUIRE(api().contacts_add(c.host(), R"({"name":"Anna Schmidt","aliases":["my daughter"],
                                           "phone_numbers":["+49 30 1234"]})",
                             &out) == MARVIN_OK);
  out = {buffer, sizeof buffer, 0};
  REQUIRE(api().contacts_find(c.host(), "My Daughter", &out) == MARVIN_OK);
  json found = json::parse(std::string(buffer, out.length));
  REQUIRE(found.size() == 1);
  CHECK(found[0]["name"] == "Anna Schmidt");
  CHECK(found[0]["phone_numbers"][0] == "+49 30 1234");
  CHECK(found[0]["sip_uris"] == json::array());
  CHECK(found[0]["emergency_order"] == 0);
  out = {buffer, sizeof buffer, 0};
  REQUIRE(api().contacts_add(c.host(), R"({"name":"Dr Weber","relation":"doctor",
                                           "sip_uris":["sip:weber@example.org"],
                                           "emergency_order":1})",
                             &out) == MARVIN_OK);
  out = {buffer, sizeof buffer, 0};
  REQUIRE(api().contacts_find(c.host(), "Dr Weber", &out) == MARVIN_OK);
  found = json::parse(std::string(buffer, out.length));
  REQUIRE(found.size() == 1);
  CHECK(found[0]["sip_uris"][0] == "sip:weber@example.org");
  CHECK(found[0]["emergency_order"] == 1);
  CHECK(api().contacts_add(c.host(), R"({"name":"X","emergency_order":"first"})", nullptr) ==
        MARVIN_ERR_INVALID);
  CHECK(std::string(api().last_error(c.host())).find("emergency_order") != std::string::npos);

  CHECK(api().contacts_add(c.host(), R"({"aliases":[]})", nullptr) == MARVIN_ERR_INVALID);
  CHECK(std::string(api().last_error(c.host())) == "contact_json: \"name\": missing");
  CHECK(w.data.list_contacts().size() == 2);

  // API 1.5: the whole book, by name (Anna was added first, Dr Weber second).
  REQUIRE(api().struct_size >= offsetof(marvin_robot_api, contacts_list) + sizeof(void*));
  out = {buffer, sizeof buffer, 0};
  REQUIRE(api().contacts_list(c.host(), &out) == MARVIN_OK);
  found = json::parse(std::string(buffer, out.length));
  REQUIRE(found.size() == 2);
  CHECK(found[0]["name"] == "Anna Schmidt");
  CHECK(found[1]["name"] == "Dr Weber");
  CHECK(found[1]["relation"] == "doctor");
  char tiny[8];
  out = {tiny, sizeof tiny, 0};
  CHECK(api().contacts_list(c.host(), &out) == MARVIN_ERR_TRUNCATED);
  CHECK(out.length > sizeof tiny);
  SkillContext without("dice", {"storage"}, w.services);
  out = {buffer, sizeof buffer, 0};
  CHECK(api().contacts_list(without.host(), &out) == MARVIN_ERR_PERMISSION);
  CHECK(std::string(api().last_error(without.host())).find("contacts") != std::string::npos);

  marvin::data::Person p;
  p.name = "Anna";
  w.data.add_person(p);
  out = {buffer, sizeof buffer, 0};
  REQUIRE(api().people_list(c.host(), &out) == MARVIN_OK);
  CHECK(json::parse(std::string(buffer, out.length))[0]["name"] == "Anna");
}

TEST_CASE("contacts_remove (API 1.7): the contact goes, the person known by face stays") {
  World w;
  SkillContext c("contacts", {"contacts"}, w.services);
  REQUIRE(api().struct_size >= offsetof(marvin_robot_api, contacts_remove) + sizeof(void*));
  marvin::data::Contact anna;
  anna.name = "Anna Schmidt";
  anna.phone_numbers = {"0123"};
  const std::int64_t anna_id = w.data.add_contact(anna);
  marvin::data::Contact tom;
  tom.name = "Tom";
  const std::int64_t tom_id = w.data.add_contact(tom);
  marvin::data::Person face;
  face.name = "Anna";
  face.contact_id = anna_id;
  w.data.add_person(face);

  SkillContext without("dice", {"storage"}, w.services);
  CHECK(api().contacts_remove(without.host(), anna_id) == MARVIN_ERR_PERMISSION);
  const std::int64_t unknown = anna_id + tom_id + 1;
  CHECK(api().contacts_remove(c.host(), unknown) == MARVIN_ERR_NOT_FOUND);
  CHECK(std::string(api().last_error(c.host())) ==
        "there is no contact with id " + std::to_string(unknown));
  CHECK(w.data.list_contacts().size() == 2);

  REQUIRE(api().contacts_remove(c.host(), anna_id) == MARVIN_OK);
  const auto left = w.data.list_contacts();
  REQUIRE(left.size() == 1);
  CHECK(left[0].name == "Tom");
  const auto people = w.data.list_people();
  REQUIRE(people.size() == 1);
  CHECK(people[0].name == "Anna");
  CHECK_FALSE(people[0].contact_id.has_value());
  CHECK(api().contacts_remove(c.host(), anna_id) == MARVIN_ERR_NOT_FOUND);
}

TEST_CASE("storage: bytes, per skill, truncation reported with the full length") {
  World w;
  SkillContext a("a", {"storage"}, w.services);
  SkillContext b("b", {"storage"}, w.services);
  const char value[] = {'x', '\0', 'y', 'z'};
  REQUIRE(api().storage_set(a.host(), "key", value, sizeof value) == MARVIN_OK);

  char small[3];
  marvin_text_out out{small, sizeof small, 0};
  CHECK(api().storage_get(a.host(), "key", &out) == MARVIN_ERR_TRUNCATED);
  CHECK(out.length == 4);
  char big[5];
  out = {big, sizeof big, 0};
  REQUIRE(api().storage_get(a.host(), "key", &out) == MARVIN_OK);
  CHECK(std::string(big, out.length) == std::string(value, sizeof value));

  out = {big, sizeof big, 0};
  CHECK(api().storage_get(b.host(), "key", &out) == MARVIN_ERR_NOT_FOUND);
  CHECK(api().storage_remove(b.host(), "key") == MARVIN_ERR_NOT_FOUND);
  CHECK(w.data.storage_get("a", "key").has_value());
}

TEST_CASE("later capabilities answer unavailable (permission first)") {
  World w;
  SkillContext granted("cam", {"vision", "phone", "smarthome"}, w.services);
  SkillContext plain("plain", {}, w.services);
  char buffer[64];
  marvin_text_out out{buffer, sizeof buffer, 0};
  // A host without a camera (API 1.2 serves vision_find_object from its camera).
  CHECK(api().vision_find_object(granted.host(), "keys", &out) == MARVIN_ERR_UNAVAILABLE);
  CHECK(std::string(api().last_error(granted.host())) == "this robot has no camera");
  CHECK(api().vision_who_is_there(granted.host(), &out) == MARVIN_ERR_UNAVAILABLE);
  CHECK(std::string(api().last_error(granted.host())) == "this robot has no camera");
  CHECK(api().phone_call(granted.host(), "+49") == MARVIN_ERR_UNAVAILABLE);
  CHECK(api().smarthome_set(granted.host(), "lamp", "on") == MARVIN_ERR_UNAVAILABLE);
  CHECK(api().phone_call(plain.host(), "+49") == MARVIN_ERR_PERMISSION);
}

TEST_CASE("time: the host's clock and zone") {
  World w;
  SkillContext c("time", {}, w.services);
  int64_t now = 0;
  CHECK(api().now(c.host(), &now) == MARVIN_OK);
  CHECK(now == 1767603600000);
  marvin_status status;
  CHECK(call_text(c.host(), api().time_zone, &status) == "Europe/Berlin");
  CHECK(status == MARVIN_OK);
  CHECK(api().now(c.host(), nullptr) == MARVIN_ERR_INVALID);
}
