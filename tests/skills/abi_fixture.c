/* A native skill written against the C ABI alone (no C++ layer), compiled several times
 * with different ids and ABI versions to test the loader. handle() says what it heard and
 * counts live instances in an exported variable. */
#include <marvin/skill.h>
#include <stdio.h>
#include <string.h>

typedef struct fixture {
  const marvin_robot_api* api;
  marvin_host* host;
} fixture;

static fixture g_instances[4];
static int g_used[4];

static void* fixture_create(const marvin_robot_api* api, marvin_host* host,
                            marvin_text_out* error) {
  for (int i = 0; i < 4; ++i) {
    if (!g_used[i]) {
      g_used[i] = 1;
      g_instances[i].api = api;
      g_instances[i].host = host;
      return &g_instances[i];
    }
  }
  if (error && error->data && error->capacity > 0) {
    error->length = (size_t)snprintf(error->data, error->capacity, "too many instances");
  }
  return NULL;
}

static void fixture_destroy(void* instance) { g_used[(fixture*)instance - g_instances] = 0; }

static marvin_status fixture_handle(void* instance, const marvin_request* request,
                                    marvin_text_out* error) {
  fixture* f = (fixture*)instance;
  char sentence[256];
  (void)error;
  snprintf(sentence, sizeof sentence, "%s heard: %s", FIXTURE_ID, request->utterance);
  return f->api->say(f->host, sentence);
}

MARVIN_EXPORT const marvin_skill_descriptor* marvin_get_skill_descriptor(void) {
  static const marvin_skill_descriptor descriptor = {sizeof(marvin_skill_descriptor),
                                                     FIXTURE_ABI_MAJOR,
                                                     FIXTURE_ABI_MINOR,
                                                     FIXTURE_ID,
                                                     fixture_create,
                                                     fixture_destroy,
                                                     fixture_handle};
  return &descriptor;
}
