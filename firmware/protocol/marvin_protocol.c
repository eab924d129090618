/* Marvin serial protocol: CRCs, encoders and the stream decoder. See marvin_protocol.h. */
#include "marvin_protocol.h"

int mv_ext_payload_len(uint8_t type) {
  switch (type) {
    case MV_STOP_ALL:
      return 0;
    case MV_HEAD_TILT:
      return 1;
    case MV_SONAR_SWEEP:
      return 4;
    case MV_LEDS:
      return 1;
    case MV_CONFIG:
      return 4;
    case MV_PING:
      return 0;
    case MV_SONAR_READING:
      return 8;
    case MV_ACK:
      return 2;
    case MV_FAULT:
      return 7;
    case MV_STATUS:
      return 12;
    default:
      return -1;
  }
}

size_t mv_frame_len(uint8_t lead) {
  if (lead == MV_END) return 1;
  if ((lead & MV_LOCO_LEAD_MASK) == MV_LOCO_LEAD_BITS) return 2;
  if ((lead & MV_LOCO_LEAD_MASK) != MV_EXT_LEAD_BITS) return 0;
  int n = mv_ext_payload_len((uint8_t)(lead & 0x3Fu));
  return n < 0 ? 0 : (size_t)n + 3u;
}

uint8_t mv_crc3(uint16_t info10) {
  unsigned crc = 0x7u;
  for (int i = 9; i >= 0; --i) {
    unsigned bit = ((info10 >> i) & 1u) ^ ((crc >> 2) & 1u);
    crc = (crc << 1) & 0x7u;
    if (bit) crc ^= 0x3u; /* x^3 + x + 1 without the x^3 term */
  }
  return (uint8_t)crc;
}

uint8_t mv_crc8(const uint8_t* bytes, size_t n) {
  unsigned crc = 0;
  for (size_t i = 0; i < n; ++i) {
    crc ^= bytes[i];
    for (int b = 0; b < 8; ++b)
      crc = (crc & 0x80u) ? ((crc << 1) ^ 0x07u) & 0xFFu : (crc << 1) & 0xFFu;
  }
  return (uint8_t)crc;
}

/* Locomotion: 10 D1 D0 S7 S6 S5 S4 | 0 S3 S2 S1 S0 C2 C1 C0 */
size_t mv_encode_locomotion(uint8_t direction, uint8_t speed, uint8_t* out) {
  if (direction > 3u) return 0;
  uint16_t info = (uint16_t)((unsigned)direction << 8 | speed);
  out[0] = (uint8_t)(0x80u | (unsigned)direction << 4 | (unsigned)speed >> 4);
  out[1] = (uint8_t)(((unsigned)speed & 0x0Fu) << 3 | mv_crc3(info));
  return 2;
}

size_t mv_encode_ext(uint8_t type, const uint8_t* payload7, size_t n, uint8_t* out) {
  int want = mv_ext_payload_len(type);
  if (type == MV_LOCOMOTION || want < 0 || (size_t)want != n) return 0;
  out[0] = (uint8_t)(0xC0u | type);
  for (size_t i = 0; i < n; ++i) {
    if (payload7[i] & 0x80u) return 0;
    out[1 + i] = payload7[i];
  }
  uint8_t crc = mv_crc8(out, n + 1);
  out[n + 1] = (uint8_t)(crc >> 7);
  out[n + 2] = (uint8_t)(crc & 0x7Fu);
  return n + 3;
}

size_t mv_encode_frame(const mv_frame* frame, uint8_t* out) {
  if (frame->type == MV_LOCOMOTION) {
    if (frame->len != 2) return 0;
    return mv_encode_locomotion(frame->payload[0], frame->payload[1], out);
  }
  return mv_encode_ext(frame->type, frame->payload, frame->len, out);
}

void mv_put14(uint8_t* p, uint16_t v) {
  p[0] = (uint8_t)((v >> 7) & 0x7Fu);
  p[1] = (uint8_t)(v & 0x7Fu);
}
uint16_t mv_get14(const uint8_t* p) {
  return (uint16_t)(((unsigned)p[0] & 0x7Fu) << 7 | (p[1] & 0x7Fu));
}
void mv_put28(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = (uint8_t)((v >> (7 * (3 - i))) & 0x7Fu);
}
uint32_t mv_get28(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v = v << 7 | (uint32_t)(p[i] & 0x7Fu);
  return v;
}

void mv_decoder_init(mv_decoder* d) {
  d->len = 0;
  d->expected = 0;
  d->overlong = 0;
  d->synced = 1;
  d->accepted = 0;
  d->rejected = 0;
}

/* Checks the frame in buf (complete, right length) and decodes it into out. */
static int check_frame(const mv_decoder* d, mv_frame* out) {
  if (d->expected == 0 || d->overlong || d->len != d->expected) return 0;
  uint8_t lead = d->buf[0];
  if ((lead & MV_LOCO_LEAD_MASK) == MV_LOCO_LEAD_BITS) {
    uint8_t dir = (uint8_t)((lead >> 4) & 0x3u);
    uint8_t speed = (uint8_t)(((unsigned)lead & 0x0Fu) << 4 | ((unsigned)d->buf[1] >> 3 & 0x0Fu));
    if (mv_crc3((uint16_t)((unsigned)dir << 8 | speed)) != (d->buf[1] & 0x7u)) return 0;
    out->type = MV_LOCOMOTION;
    out->len = 2;
    out->payload[0] = dir;
    out->payload[1] = speed;
    return 1;
  }
  size_t n = (size_t)d->len - 3u;
  uint8_t crc = mv_crc8(d->buf, n + 1);
  if (d->buf[n + 1] != (crc >> 7) || d->buf[n + 2] != (crc & 0x7Fu)) return 0;
  out->type = (uint8_t)(lead & 0x3Fu);
  out->len = (uint8_t)n;
  for (size_t i = 0; i < n; ++i) out->payload[i] = d->buf[1 + i];
  return 1;
}

/* Closes the frame in progress at a delimiter. Returns 1 if it is accepted. */
static int finish(mv_decoder* d, mv_frame* out) {
  if (d->len == 0) return 0;
  int ok = check_frame(d, out);
  int accepted = ok && d->synced;
  if (ok) {
    d->synced = 1;
  } else {
    d->synced = 0;
    d->rejected++;
  }
  if (ok && !accepted) d->rejected++;
  if (accepted) d->accepted++;
  d->len = 0;
  d->overlong = 0;
  return accepted;
}

int mv_decoder_push(mv_decoder* d, uint8_t byte, mv_frame* out) {
  if (byte == MV_END) {
    int r = finish(d, out);
    d->synced = 1;
    return r;
  }
  if (byte & 0x80u) {
    int r = finish(d, out);
    d->buf[0] = byte;
    d->len = 1;
    d->expected = (uint8_t)mv_frame_len(byte);
    return r;
  }
  if (d->len == 0) { /* orphan continuation byte */
    d->synced = 0;
    d->rejected++;
    return 0;
  }
  if (d->len >= d->expected || d->len >= MV_MAX_FRAME) {
    d->overlong = 1;
    return 0;
  }
  d->buf[d->len++] = byte;
  return 0;
}

int mv_decoder_idle(mv_decoder* d, mv_frame* out) { return mv_decoder_push(d, MV_END, out); }
