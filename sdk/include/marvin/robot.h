/* Marvin SDK: the Robot API, the table of host functions a skill may call.
 *
 * The host hands a skill a pointer to one marvin_robot_api and a marvin_host context.
 * The table stays valid for the lifetime of the skill instance. Every function takes the
 * context first and returns a marvin_status; on any status but MARVIN_OK,
 * api->last_error(host) gives a sentence saying what went wrong (for example
 * "permission 'motion' is not granted to skill 'dice'").
 *
 * Permissions (declared in skill.json, approved by the owner at install):
 *   "speech"    say, ask               (every skill has it implicitly)
 *   "light"     set_light
 *   "motion"    move, stop, tilt_head, go_to, go_stop (API 1.2), guide_to (API 1.4)
 *   "sensors"   obstacle_scan, where_am_i (API 1.2)
 *   "schedule"  schedule_* (schedule_snooze, schedule_done, schedule_last_fired: API 1.1)
 *   "contacts"  contacts_*, people_list (contacts_list: API 1.5; contacts_remove: 1.7)
 *   "storage"   storage_*             (a skill only ever sees its own keys)
 *   "camera"    vision_look, vision_capture_photo (API 1.2)
 *   "faces"     vision_enroll_face, vision_forget_face (API 1.2): who the robot knows
 *   "smarthome" smarthome_set, smarthome_devices (API 1.2)
 *   "events"    events_list (API 1.3): the owner's event log (who came while out)
 *   "phone"     phone_call, phone_* (API 1.3)
 *   "vision", "phone"                 the capabilities of later releases
 * Calls without the permission fail with MARVIN_ERR_PERMISSION and change nothing.
 *
 * Threading: a skill instance is called by one host thread at a time; it may call the
 * table from that thread only. Calls that wait for the user (ask) or the body (move)
 * return MARVIN_ERR_CANCELLED when the user says "stop". */
#ifndef MARVIN_ROBOT_H_
#define MARVIN_ROBOT_H_

#include "marvin/abi.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The robot's head LEDs: what the robot is doing, at a glance. */
typedef enum marvin_light {
  MARVIN_LIGHT_OFF = 0,
  MARVIN_LIGHT_AWAITING = 1,  /* red: waiting for the wake word */
  MARVIN_LIGHT_LISTENING = 2, /* green: listening to a request */
  MARVIN_LIGHT_EXECUTING = 3  /* yellow: acting on a request */
} marvin_light;

typedef enum marvin_direction {
  MARVIN_FORWARD = 0,
  MARVIN_BACKWARD = 1,
  MARVIN_TURN_LEFT = 2,
  MARVIN_TURN_RIGHT = 3
} marvin_direction;

/* One sonar reading. The sonar sweeps in the vertical plane of the robot's heading. */
typedef struct marvin_scan_point {
  double angle_deg;   /* 0 straight ahead, 90 straight up, 120 up and backwards */
  double distance_m;  /* 0..2.5 (slant distance); 2.5 means nothing closer */
  int64_t time_ms;    /* when it was read: host clock, milliseconds since the Unix epoch */
} marvin_scan_point;

typedef enum marvin_log_level {
  MARVIN_LOG_DEBUG = 0,
  MARVIN_LOG_INFO = 1,
  MARVIN_LOG_WARNING = 2,
  MARVIN_LOG_ERROR = 3
} marvin_log_level;

/* Since API 1.4 (guide_to): called on the skill's own thread, between two of the robot's
 * control steps, with one thing worth telling the person being guided, as JSON:
 *   {"event": "start" | "turn" | "obstacle" | "step_down",
 *    "distance_left_m": 6.2 (along the path, every event),
 *    "turn": "left" | "right" ("turn": the next turn of the path, "distance_m" ahead),
 *    "distance_m": 0.9 (horizontal, from the robot),
 *    "kind": "wall" (echoes from high up too) | "low" (below the knees) | "step",
 *    "stopped": true when the robot stopped for it ("obstacle"; always for "step_down")}
 * "start" comes once the path is planned; "turn" once per turn, about a metre before it;
 * "obstacle" for something the sonar found within a metre (at most every 3 s unless the
 * robot stops for it); "step_down" for a drop in the floor ahead (the robot stopped and
 * will not drive into it). The sonar looks straight ahead, so an obstacle is "ahead";
 * vision_look may be called here to name it. Return 0 to go on, anything else to stop:
 * guide_to then stops the wheels and returns MARVIN_ERR_CANCELLED. The robot waits while
 * the callback runs (it is safe: each drive command lasts 300 ms), so return quickly. */
typedef int (*marvin_guide_event_fn)(void* user, const char* event_json);

#define MARVIN_ROBOT_API_MAJOR 1
#define MARVIN_ROBOT_API_MINOR 7

typedef struct marvin_robot_api {
  uint32_t struct_size; /* sizeof(marvin_robot_api) as the host compiled it */
  uint16_t major;       /* MARVIN_ROBOT_API_MAJOR */
  uint16_t minor;       /* MARVIN_ROBOT_API_MINOR */

  /* The sentence describing why the last call from this context failed ("" if none).
   * Valid until the next call on the same context. Never NULL. */
  const char* (*last_error)(marvin_host* host);

  /* --- speech ------------------------------------------------------------------- */
  /* Speaks `text` to the user. Returns when the sentence is queued for speaking. */
  marvin_status (*say)(marvin_host* host, const char* text);
  /* Speaks `question`, waits for the user's answer and writes its text to `answer`. */
  marvin_status (*ask)(marvin_host* host, const char* question, marvin_text_out* answer);

  /* --- body ---------------------------------------------------------------------- */
  marvin_status (*set_light)(marvin_host* host, marvin_light light);
  /* Drives for `duration_ms` at `speed` (0..255) then stops; the base stops by itself
   * before an obstacle. Returns when the motion has finished or was stopped. */
  marvin_status (*move)(marvin_host* host, marvin_direction direction, uint8_t speed,
                        uint32_t duration_ms);
  marvin_status (*stop)(marvin_host* host);
  /* Tilts the head to `degrees` above level (-60 looks down, 0 level, +60 up);
   * MARVIN_ERR_INVALID outside -60..60. */
  marvin_status (*tilt_head)(marvin_host* host, int32_t degrees);
  /* Copies the latest obstacle scan, ordered by angle, into `points` (at most `capacity`)
   * and sets `*count` to the number copied; MARVIN_ERR_TRUNCATED if there were more. */
  marvin_status (*obstacle_scan)(marvin_host* host, marvin_scan_point* points, size_t capacity,
                                 size_t* count);

  /* --- time ---------------------------------------------------------------------- */
  /* Now, in milliseconds since the Unix epoch (UTC), from the host's clock. */
  marvin_status (*now)(marvin_host* host, int64_t* unix_ms);
  /* The owner's IANA time zone name, e.g. "Europe/Berlin". */
  marvin_status (*time_zone)(marvin_host* host, marvin_text_out* name);

  /* --- schedules (JSON text; the format is documented in sdk/include/marvin/README.md)
   * schedule_add takes {"title", "at" (local "YYYY-MM-DDTHH:MM"), "recurrence"?} and
   * writes the new reminder's JSON (with "id") once it is durably stored. */
  marvin_status (*schedule_add)(marvin_host* host, const char* reminder_json,
                                marvin_text_out* created_json);
  /* Reminders firing in [from_unix_ms, to_unix_ms), as a JSON array. */
  marvin_status (*schedule_list)(marvin_host* host, int64_t from_unix_ms, int64_t to_unix_ms,
                                 marvin_text_out* reminders_json);
  marvin_status (*schedule_remove)(marvin_host* host, int64_t reminder_id);

  /* --- contacts and people (JSON text) -------------------------------------------- */
  /* Contacts whose name or alias matches `name` (case-insensitive), as a JSON array. */
  marvin_status (*contacts_find)(marvin_host* host, const char* name, marvin_text_out* contacts_json);
  marvin_status (*contacts_add)(marvin_host* host, const char* contact_json,
                                marvin_text_out* created_json);
  marvin_status (*people_list)(marvin_host* host, marvin_text_out* people_json);

  /* --- per-skill key-value storage (values are bytes; keys are text) ------------- */
  marvin_status (*storage_get)(marvin_host* host, const char* key, marvin_text_out* value);
  marvin_status (*storage_set)(marvin_host* host, const char* key, const char* value,
                               size_t value_length);
  marvin_status (*storage_remove)(marvin_host* host, const char* key);

  /* --- the skill's own log (shown by `marvin skills list` and in the host log) ---- */
  marvin_status (*log)(marvin_host* host, marvin_log_level level, const char* message);

  /* True once the user said "stop" or the time limit ran out: long skills poll it. */
  int (*is_cancelled)(marvin_host* host);

  /* --- later capabilities: present now, MARVIN_ERR_UNAVAILABLE until they land ---- */
  /* Since API 1.2 (permission "camera" or "vision"): whether an object taught with
   * vision_teach_object is in view now: {"name", "found": true|false, "box": [x, y, w, h]}.
   * A name nothing was taught as but that names a COCO class ("phone", "mug") is looked
   * for by the object detector, when the host has one: "name" is then what the host calls
   * it ("phone"; looks and sightings use that name) and "class" the COCO class.
   * MARVIN_ERR_NOT_FOUND if nothing of that name was taught and no detector knows it. */
  marvin_status (*vision_find_object)(marvin_host* host, const char* object_name,
                                      marvin_text_out* result_json);
  /* Since API 1.2 (permission "camera" or "vision"): the faces in view,
   * [{"name": "Anna" | "", "box": [x, y, w, h]}] (vision_look says more). */
  marvin_status (*vision_who_is_there)(marvin_host* host, marvin_text_out* people_json);
  marvin_status (*phone_call)(marvin_host* host, const char* phone_number);
  /* Smart home (real since API 1.2; MARVIN_ERR_UNAVAILABLE on older hosts): sets device
   * `device` (an id from smarthome_devices, or the name or alias of exactly one device) to
   * `state`: "on", "off", or JSON {"on": true|false, "brightness": 0..100} (either or both);
   * since API 1.6 a thermostat also takes "target_temperature" (degrees Celsius, within its
   * "min_temperature".."max_temperature"; "on": false is heating off, when "switchable").
   * Returns MARVIN_OK only once the device itself reported the new state through the home's
   * broker; MARVIN_ERR_UNAVAILABLE when there is no broker connection, the device is offline
   * or did not answer within a few seconds (last_error says which), MARVIN_ERR_NOT_FOUND
   * for an unknown or ambiguous device, MARVIN_ERR_INVALID for a malformed state. */
  marvin_status (*smarthome_set)(marvin_host* host, const char* device, const char* state);

  /* --- since API 1.1: answering a reminder that fired ("snooze", "I took them") ------
   * A skill built against 1.1 running on a 1.0 host must check struct_size (or minor)
   * before calling these: they lie beyond the end of an older host's table. */
  /* "Remind me again in ten minutes": reminder `reminder_id` fires next at
   * `until_unix_ms` (a done one-off reminder becomes active again); a recurring one goes
   * on with its series after that. MARVIN_ERR_NOT_FOUND if there is no active or done
   * reminder with that id; MARVIN_ERR_INVALID if `until_unix_ms` is not in the future. */
  marvin_status (*schedule_snooze)(marvin_host* host, int64_t reminder_id, int64_t until_unix_ms);
  /* "I took them": a one-off reminder becomes done and will not fire again; a recurring
   * one keeps its series. Either way the owner's event log gets a "reminder_done" event,
   * also for a one-off that is already done (it fired). MARVIN_ERR_NOT_FOUND if there is
   * no active or done reminder with that id (never was, or cancelled). */
  marvin_status (*schedule_done)(marvin_host* host, int64_t reminder_id);
  /* The reminder the robot announced most recently ("Reminder: take my pills"), as the
   * JSON of one reminder (the format of schedule_list's elements, with its current
   * state), so a skill knows which reminder "done" or "snooze" refers to.
   * MARVIN_ERR_NOT_FOUND if no reminder has fired since the host started. */
  marvin_status (*schedule_last_fired)(marvin_host* host, marvin_text_out* reminder_json);

  /* --- since API 1.2: seeing (the camera, faces and objects) -------------------------
   * Check struct_size (or minor) before calling these on an older host.
   * A robot without a working camera answers MARVIN_ERR_UNAVAILABLE with a sentence
   * naming the camera and what went wrong. */
  /* What the camera sees now, as JSON:
   *   {"width": 640, "height": 480,
   *    "faces":   [{"name": "Anna" | "" (someone unknown), "box": [x, y, w, h],
   *                 "distance": 0.12 (squared L2 to the nearest enrolled face, -1: none)}],
   *    "objects": [{"label": "phone", "class": "cell phone", "box": [x, y, w, h],
   *                 "score": 0.8}]}
   * Objects are the COCO things the detector knows ("label": the name people use, "class":
   * COCO's; "person" included) and the things the user taught (vision_teach_object: the
   * taught name, no "class"). Boxes are in pixels of that frame. Permission "camera". */
  marvin_status (*vision_look)(marvin_host* host, marvin_text_out* seen_json);
  /* Takes a photo (JPEG) and writes the file's path. Photos are only kept when the user
   * asked for one; the skill owns the file. Permission "camera". */
  marvin_status (*vision_capture_photo)(marvin_host* host, marvin_text_out* photo_path);
  /* "This is Anna": learns the face in front of the camera from up to `frames` frames
   * (1..20) and writes {"name", "frames_used"}. Exactly one face must be in view:
   * MARVIN_ERR_NOT_FOUND when there is none, MARVIN_ERR_INVALID when there are several.
   * Consent: a skill calls this only after the owner confirmed. Permission "faces". */
  marvin_status (*vision_enroll_face)(marvin_host* host, const char* name, uint32_t frames,
                                      marvin_text_out* result_json);
  /* "Forget Anna's face": removes the person and every embedding of their face.
   * MARVIN_ERR_NOT_FOUND if nobody of that name is enrolled. Permission "faces". */
  marvin_status (*vision_forget_face)(marvin_host* host, const char* name);
  /* "These are my keys": learns the look of the thing held up in the middle of the view
   * (its features, not a photo) so vision_find_object can find it later.
   * MARVIN_ERR_INVALID when it is too plain to recognise. Permission "camera". */
  marvin_status (*vision_teach_object)(marvin_host* host, const char* name);

  /* --- since API 1.2: going places -----------------------------------------------
   * The robot plans a path on its floor plan and drives it, stopping and re-planning
   * when the sonar sees something in the way. Check struct_size (or minor) before
   * calling these on an older host. */
  /* Drives to `place` and returns once there: a room ("kitchen"), a named place ("the
   * sofa"), a person's last known spot ("Anna") or "me" (the robot's owner). Case and a
   * leading "the" do not matter. MARVIN_ERR_NOT_FOUND for a place the map does not know;
   * MARVIN_ERR_UNAVAILABLE when the robot gave up, with last_error saying why in words the
   * user understands ("the kitchen door is blocked") or when the robot has no map;
   * MARVIN_ERR_CANCELLED when the user said "stop" (the wheels are stopped then). */
  marvin_status (*go_to)(marvin_host* host, const char* place);
  /* Stops going places and the wheels now. */
  marvin_status (*go_stop)(marvin_host* host);
  /* The room the robot believes it is in ("kitchen"). MARVIN_ERR_NOT_FOUND between rooms
   * (in a doorway) or outside every room. */
  marvin_status (*where_am_i)(marvin_host* host, marvin_text_out* room);

  /* --- since API 1.2: smart home ------------------------------------------------------
   * The devices the robot can control, with the state they reported last, as JSON:
   *   {"connected": true, "room": "living room",
   *    "devices": [{"id": "z2m:kitchen/kitchen light", "name": "kitchen light",
   *                 "room": "kitchen", "type": "light", "dimmable": true,
   *                 "aliases": ["the big lamp"], "available": true,
   *                 "on": false, "brightness": 100}]}
   * "connected": whether the home's broker is reachable now; "room": where the robot is;
   * "on"/"brightness" are null until the device reported them.
   * Since API 1.6, "type" may be "thermostat" (heating), with "target_temperature" (the set
   * point) and "temperature" (what it measures), in degrees Celsius or null until reported,
   * "min_temperature", "max_temperature", and "switchable" (whether "on" can be set: its
   * heating can be turned off; "on" is true while it heats, whatever its mode). */
  marvin_status (*smarthome_devices)(marvin_host* host, marvin_text_out* devices_json);

  /* --- since API 1.3: finding and guarding --------------------------------------------
   * Check struct_size (or minor) before calling these on an older host. Every known
   * person and object the camera sees (through vision_look or look_around) is recorded
   * as a sighting: what, the room, the furniture it is near, when. */
  /* Turns in place through a full circle in `stops` stops (4 to 12; 0 means 8), looks at
   * each stop and writes what was seen, as JSON:
   *   {"stops": 8, "seen": [{"kind": "person" | "object", "name": "Anna" | "" (a face
   *     nobody enrolled) | "keys", "bearing_deg": 40 (from the heading when it started,
   *     counter-clockwise), "distance_m": 1.8 (an estimate), "room": "kitchen",
   *     "near": "kitchen table" | ""}]}
   * Permissions "camera" and "motion". MARVIN_ERR_CANCELLED when the user said "stop";
   * MARVIN_ERR_UNAVAILABLE without a camera or a map. */
  marvin_status (*look_around)(marvin_host* host, uint32_t stops, marvin_text_out* seen_json);
  /* Where `what` ("Anna", "keys"; "" for everything) was last seen, newest first, only
   * sightings at or after `since_unix_ms` (0: all):
   *   [{"what": "keys", "kind": "object", "room": "kitchen", "near": "kitchen table",
   *     "seen_unix_ms": 1764100000000}]
   * Permission "camera". */
  marvin_status (*sightings_find)(marvin_host* host, const char* what, int64_t since_unix_ms,
                                  marvin_text_out* sightings_json);
  /* The rooms in the order a search visits them from where the robot is, as a JSON list
   * of names (the room it is in first). Permission "sensors". */
  marvin_status (*rooms_to_search)(marvin_host* host, marvin_text_out* rooms_json);
  /* What `name` is on the robot's map: {"name": "Anna", "kind": "room" | "place" |
   * "person", "room": "living room", "distance_m": 6.2}. "distance_m" (added in API 1.6,
   * optional: treat it as unknown when absent) is how far the robot would drive to get
   * there from where it is now, along its path; absent while the robot is driving or when
   * no path leads there. MARVIN_ERR_NOT_FOUND if the map has no such name.
   * Permission "sensors". */
  marvin_status (*place_find)(marvin_host* host, const char* name, marvin_text_out* place_json);
  /* Turns in place by `degrees` (-360 to 360, counter-clockwise positive) and returns when
   * done. Permission "motion". MARVIN_ERR_CANCELLED on "stop". */
  marvin_status (*turn)(marvin_host* host, int32_t degrees);
  /* Guard mode. `mode` 1: on (the robot watches and alerts on a face nobody enrolled seen
   * over several frames: it says so, saves a photo in the data directory, logs an
   * "intruder" event and publishes it on the message bus). 0: off, only while a known
   * face is in view now: MARVIN_ERR_PERMISSION otherwise ("I can only stop guarding for
   * someone I know"). -1: only report. Writes {"on": true, "since_unix_ms": ...,
   * "alerts": 1, "by": "Anna" (who turned it off)}. Permission "camera". */
  marvin_status (*guard)(marvin_host* host, int32_t mode, marvin_text_out* state_json);
  /* Events from the owner's event log, newest first, of `kind` ("intruder",
   * "reminder_done"; "" for all) at or after `since_unix_ms`: [{"kind", "message",
   * "time_unix_ms"}]. Permission "events". */
  marvin_status (*events_list)(marvin_host* host, const char* kind, int64_t since_unix_ms,
                               marvin_text_out* events_json);
  /* --- since API 1.3: phone calls -------------------------------------------------
   * Permission "phone". Check struct_size (or minor) before calling these on an older
   * host. A robot without a telephone answers MARVIN_ERR_UNAVAILABLE. One call at a time.
   * The 1.0 phone_call(host, number) is real since 1.3: it dials like phone_dial and
   * returns at once. Calls the robot places and their progress are the calling skill's to
   * speak (it reads them with phone_wait_event); the host itself announces incoming calls
   * ("Anna is calling"), a call the other side ended and the steps of a call for help,
   * and logs every call for help in the event log. */
  /* Who `who` means, as heard: "my daughter", "the doctor", "Anna", "0123 456 789",
   * "sip:anna@example.org". Writes {"kind": "contact"|"number"|"ambiguous"|"no_number"|
   * "unknown", "name", "number" (what phone_dial takes), "candidates": ["Anna Schmidt",
   * ...], "say": the confirmation question ("Call Anna Schmidt on 0123 456?") or what to
   * tell the user ("I have no number for Tom.")}. Reads the contacts (no "contacts"
   * permission needed: "phone" covers it). */
  marvin_status (*phone_resolve)(marvin_host* host, const char* who, marvin_text_out* callee_json);
  /* Starts a call to `number` (a phone number or a sip: URI; `name`, may be "", is who the
   * host names in announcements). Returns once dialling started; the progress comes from
   * phone_wait_event. MARVIN_ERR_INVALID for something that is no number;
   * MARVIN_ERR_UNAVAILABLE when a call is already going on or the telephone cannot call
   * (last_error says which: "a call with Anna is going on", "the phone is not running"). */
  marvin_status (*phone_dial)(marvin_host* host, const char* number, const char* name);
  /* Ends the current call or declines the ringing incoming one; MARVIN_ERR_NOT_FOUND when
   * there is none. */
  marvin_status (*phone_hang_up)(marvin_host* host);
  /* Answers the ringing incoming call; MARVIN_ERR_NOT_FOUND when nobody is calling. */
  marvin_status (*phone_answer)(marvin_host* host);
  /* Declines the ringing incoming call; MARVIN_ERR_NOT_FOUND when nobody is calling. */
  marvin_status (*phone_decline)(marvin_host* host);
  /* The call now: {"state": "idle"|"calling"|"ringing"|"in_call"|"incoming",
   * "number": "<the other side>", "name": "<their contact name, or the number>"}. */
  marvin_status (*phone_state)(marvin_host* host, marvin_text_out* state_json);
  /* Waits up to `timeout_ms` for the next event of the call this skill placed (or the
   * call for help it started) and writes it:
   *   {"event": "ringing"|"answered"|"busy"|"no_answer"|"ended"|"failed"|
   *             "emergency_step"|"emergency_done", "name", "number",
   *    "reason": SIP's words for "failed"/"ended", "text": the sentence of an
   *    emergency_step, "answered_by": "<name>" or "" (nobody) for emergency_done}.
   * MARVIN_ERR_NOT_FOUND when nothing happened in time; MARVIN_ERR_CANCELLED when the user
   * said "stop" (the call goes on: hang up if that is what "stop" means). */
  marvin_status (*phone_wait_event)(marvin_host* host, uint32_t timeout_ms,
                                    marvin_text_out* event_json);
  /* "Call for help": no question asked; calls the emergency contacts in their order
   * (`marvin contacts add --emergency N`) until one answers, logging each step. Returns
   * once the sequence started; its steps come from phone_wait_event. MARVIN_ERR_NOT_FOUND
   * when there is no emergency contact with a number. */
  marvin_status (*phone_call_for_help)(marvin_host* host);

  /* --- since API 1.4: guiding ------------------------------------------------------
   * Check struct_size (or minor) before calling this on an older host. */
  /* go_to for leading a person: drives to `place` (as go_to takes it) at `speed_percent`
   * (10..100; 0 means 50, a slow walk) of the robot's normal driving speed, stops for
   * obstacles and steps down and plans around them, and calls `on_event` (may be NULL)
   * with `user` for each thing worth telling on the way (marvin_guide_event_fn above).
   * Returns as go_to does: MARVIN_OK once there; MARVIN_ERR_NOT_FOUND for a place the map
   * does not know; MARVIN_ERR_UNAVAILABLE when no way is left (last_error says why: "there
   * is a step down on the way to the garden"); MARVIN_ERR_CANCELLED on "stop" or when
   * on_event asked to stop; MARVIN_ERR_INVALID for a speed above 100. Permission "motion". */
  marvin_status (*guide_to)(marvin_host* host, const char* place, uint32_t speed_percent,
                            marvin_guide_event_fn on_event, void* user);

  /* --- since API 1.5: the whole contact book ----------------------------------------
   * Check struct_size (or minor) before calling this on an older host. */
  /* Every contact ("who are my contacts?"), sorted by name, as a JSON array of the objects
   * contacts_find writes; [] when there are none. Permission "contacts". */
  marvin_status (*contacts_list)(marvin_host* host, marvin_text_out* contacts_json);

  /* --- since API 1.7: forgetting a contact -------------------------------------------
   * Check struct_size (or minor) before calling this on an older host. */
  /* Removes the contact with this id, as contacts_find and contacts_list write it ("delete
   * Peter from my contacts"): its numbers, addresses and nicknames go with it; a person
   * known by face stays, no longer linked to it. MARVIN_ERR_NOT_FOUND when there is no
   * such contact. Permission "contacts". */
  marvin_status (*contacts_remove)(marvin_host* host, int64_t contact_id);
} marvin_robot_api;

#ifdef __cplusplus
}
#endif

#endif /* MARVIN_ROBOT_H_ */
