/* Marvin SDK: ABI version and the basic types shared by skills and the host.
 *
 * Versioning: the host accepts a skill whose ABI major equals the host's and whose
 * minor is not newer than the host's. Minor versions only append: new functions go at
 * the end of marvin_robot_api, new fields at the end of structs, each struct starts
 * with its size so either side can tell what the other knows.
 *
 * Strings crossing the ABI are UTF-8 and NUL-terminated. Strings passed in are
 * borrowed for the duration of the call. Strings handed back are written into a buffer
 * owned by the caller (see marvin_text_out). Nothing crossing this boundary is a C++ type,
 * and no C++ exception may cross it in either direction. */
#ifndef MARVIN_ABI_H_
#define MARVIN_ABI_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MARVIN_ABI_MAJOR 1
#define MARVIN_ABI_MINOR 5

#if defined(__GNUC__)
#define MARVIN_EXPORT __attribute__((visibility("default")))
#else
#define MARVIN_EXPORT
#endif

/* Result of every call across the ABI. */
typedef enum marvin_status {
  MARVIN_OK = 0,
  MARVIN_ERR_PERMISSION = 1,  /* the skill's manifest does not grant this call */
  MARVIN_ERR_UNAVAILABLE = 2, /* the robot has no such capability (yet), or it is offline */
  MARVIN_ERR_INVALID = 3,     /* an argument is malformed; the message says which */
  MARVIN_ERR_NOT_FOUND = 4,   /* no such contact, reminder, key, ... */
  MARVIN_ERR_CANCELLED = 5,   /* the user said "stop", or the time limit ran out */
  MARVIN_ERR_TRUNCATED = 6,   /* the output buffer was too small; see marvin_text_out */
  MARVIN_ERR_INTERNAL = 7     /* anything else; the message says what */
} marvin_status;

/* A caller-owned output buffer for text the callee returns. The callee writes at most
 * `capacity` bytes including the NUL and always sets `length` to the full length of the
 * text (without NUL). When the text did not fit it returns MARVIN_ERR_TRUNCATED and the
 * caller may retry with a buffer of at least length + 1 bytes.
 *
 * Calls that act and write text (ask, schedule_add, contacts_add, vision_capture_photo,
 * vision_enroll_face, look_around, guard, phone_wait_event) do not act twice for such a
 * retry: the host keeps the answer that did not fit, and the skill's very next Robot API
 * call, if it is the same function with the same arguments, gets the kept answer without
 * acting again. Any other call in between (last_error and is_cancelled excepted), or the
 * next request, drops the kept answer; the same call after that acts again. Since host
 * API 1.3; the ABI is unchanged (no new function, field or status). */
typedef struct marvin_text_out {
  char* data;
  size_t capacity;
  size_t length;
} marvin_text_out;

/* Opaque: the host's context for one skill instance. Passed back to every Robot API
 * call so the host knows which skill is calling (its permissions and storage). */
typedef struct marvin_host marvin_host;

#ifdef __cplusplus
}
#endif

#endif /* MARVIN_ABI_H_ */
