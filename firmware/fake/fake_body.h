/* The fake layer: a mv_hal that records what the core asked of the body, for host tests.
 * Telemetry sent by the core is decoded back into frames. */
#ifndef MARVIN_FAKE_BODY_H_
#define MARVIN_FAKE_BODY_H_

#include "../core/marvin_core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MV_FAKE_MAX_SENT 64

typedef struct mv_fake_body {
  mv_hal hal;
  uint8_t speed[2];
  uint8_t backward[2];
  int8_t head_deg;
  uint8_t sonar_deg;
  uint8_t leds;
  uint32_t motor_calls;
  /* telemetry, decoded; the oldest are dropped when full */
  mv_decoder tx_decoder;
  mv_frame sent[MV_FAKE_MAX_SENT];
  size_t sent_count;
  uint32_t sent_bytes;
} mv_fake_body;

void mv_fake_body_init(mv_fake_body* body);
/* Number of sent frames of this type and the last one (NULL if none). */
size_t mv_fake_count(const mv_fake_body* body, uint8_t type);
const mv_frame* mv_fake_last(const mv_fake_body* body, uint8_t type);
void mv_fake_clear(mv_fake_body* body);

#ifdef __cplusplus
}
#endif

#endif /* MARVIN_FAKE_BODY_H_ */
