/* The fake layer for host tests. See fake_body.h. */
#include "fake_body.h"

#include <string.h>

static void set_motor(void* ctx, uint8_t side, uint8_t backward, uint8_t speed) {
  mv_fake_body* b = (mv_fake_body*)ctx;
  b->speed[side & 1u] = speed;
  b->backward[side & 1u] = backward;
  b->motor_calls++;
}
static void set_head(void* ctx, int8_t degrees) { ((mv_fake_body*)ctx)->head_deg = degrees; }
static void set_sonar_servo(void* ctx, uint8_t degrees) {
  ((mv_fake_body*)ctx)->sonar_deg = degrees;
}
static void set_leds(void* ctx, uint8_t bits) { ((mv_fake_body*)ctx)->leds = bits; }
static void send(void* ctx, const uint8_t* bytes, size_t n) {
  mv_fake_body* b = (mv_fake_body*)ctx;
  for (size_t i = 0; i < n; ++i) {
    mv_frame f;
    b->sent_bytes++;
    if (!mv_decoder_push(&b->tx_decoder, bytes[i], &f)) continue;
    if (b->sent_count == MV_FAKE_MAX_SENT) {
      memmove(&b->sent[0], &b->sent[1], sizeof(mv_frame) * (MV_FAKE_MAX_SENT - 1));
      b->sent_count--;
    }
    b->sent[b->sent_count++] = f;
  }
}

void mv_fake_body_init(mv_fake_body* body) {
  memset(body, 0, sizeof *body);
  body->hal.ctx = body;
  body->hal.set_motor = set_motor;
  body->hal.set_head = set_head;
  body->hal.set_sonar_servo = set_sonar_servo;
  body->hal.set_leds = set_leds;
  body->hal.send = send;
  mv_decoder_init(&body->tx_decoder);
}

size_t mv_fake_count(const mv_fake_body* body, uint8_t type) {
  size_t n = 0;
  for (size_t i = 0; i < body->sent_count; ++i) n += body->sent[i].type == type;
  return n;
}

const mv_frame* mv_fake_last(const mv_fake_body* body, uint8_t type) {
  for (size_t i = body->sent_count; i-- > 0;)
    if (body->sent[i].type == type) return &body->sent[i];
  return NULL;
}

void mv_fake_clear(mv_fake_body* body) { body->sent_count = 0; }
