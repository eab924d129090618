/* Marvin SDK: what a native skill exports.
 *
 * A native skill is a shared library exporting one C function,
 *
 *     MARVIN_EXPORT const marvin_skill_descriptor* marvin_get_skill_descriptor(void);
 *
 * which returns a pointer to static data. (The function cannot share the name of the
 * marvin_skill_descriptor type: C and C++ both reject that.) The host reads the skill's
 * skill.json first, dlopen()s the library, calls marvin_get_skill_descriptor() and checks
 * abi_major/abi_minor before calling anything else. C++ skills use the macro of marvin/skill.hpp instead of
 * writing this by hand.
 *
 * Life cycle: create() once per instance; handle() once per recognised request, never on
 * two threads at once for the same instance; destroy() once. A skill reports failure by
 * returning a status and writing a sentence into `error`; it never lets an exception or a
 * longjmp escape. */
#ifndef MARVIN_SKILL_H_
#define MARVIN_SKILL_H_

#include "marvin/abi.h"
#include "marvin/robot.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One recognised request, as the skill manager hands it to the skill. */
typedef struct marvin_request {
  uint32_t struct_size;
  const char* intent;      /* the intent name from skill.json, e.g. "roll" */
  const char* slots_json;  /* {"slot": value, ...}: every required slot is present */
  const char* utterance;   /* what the user said, normalised */
} marvin_request;

typedef struct marvin_skill_descriptor {
  uint32_t struct_size; /* sizeof(marvin_skill_descriptor) as the skill compiled it */
  uint16_t abi_major;   /* MARVIN_ABI_MAJOR the skill was built with */
  uint16_t abi_minor;   /* MARVIN_ABI_MINOR the skill was built with */
  const char* skill_id; /* must equal "id" in the skill's skill.json */

  /* Makes an instance. `api` and `host` stay valid until destroy(). Returns NULL on
   * failure with a sentence in `error`. */
  void* (*create)(const marvin_robot_api* api, marvin_host* host, marvin_text_out* error);
  void (*destroy)(void* instance);
  /* Acts on one request. */
  marvin_status (*handle)(void* instance, const marvin_request* request, marvin_text_out* error);
} marvin_skill_descriptor;

typedef const marvin_skill_descriptor* (*marvin_skill_descriptor_fn)(void);
#define MARVIN_SKILL_DESCRIPTOR_SYMBOL "marvin_get_skill_descriptor"

#ifdef __cplusplus
}
#endif

#endif /* MARVIN_SKILL_H_ */
