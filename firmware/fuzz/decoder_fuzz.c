/* libFuzzer target: the stream decoder and the core behind it. Built by firmware/ci.sh
 * with clang (-fsanitize=fuzzer,address,undefined) and run briefly with a fixed seed.
 * Checks: no crash or UB; the decoder's buffer stays in bounds; every accepted frame
 * re-encodes to bytes that decode to the same frame. */
#include <stdlib.h>
#include <string.h>

#include "core/marvin_core.h"
#include "fake/fake_body.h"
#include "protocol/marvin_protocol.h"

static void check_round_trip(const mv_frame* f) {
  uint8_t buf[MV_MAX_FRAME + 1];
  size_t n = mv_encode_frame(f, buf);
  if (n == 0) abort(); /* an accepted frame must be encodable */
  buf[n++] = MV_END;
  mv_decoder d;
  mv_decoder_init(&d);
  mv_frame g;
  int got = 0;
  for (size_t i = 0; i < n; ++i) got += mv_decoder_push(&d, buf[i], &g);
  if (got != 1 || g.type != f->type || g.len != f->len ||
      memcmp(g.payload, f->payload, f->len) != 0)
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mv_decoder d;
  mv_decoder_init(&d);
  static mv_fake_body body;
  static mv_core core;
  mv_fake_body_init(&body);
  mv_core_init(&core, &body.hal, NULL, 0);
  uint32_t now = 0;
  for (size_t i = 0; i < size; ++i) {
    mv_frame f;
    if (mv_decoder_push(&d, data[i], &f)) check_round_trip(&f);
    if (d.len > MV_MAX_FRAME) abort();
    now += data[i] & 0x0Fu;
    mv_core_rx(&core, data[i], now);
    mv_core_tick(&core, now);
    uint8_t angle;
    if (mv_core_ping_due(&core, now, &angle)) mv_core_echo(&core, (uint32_t)data[i] * 100u, now);
  }
  return 0;
}
