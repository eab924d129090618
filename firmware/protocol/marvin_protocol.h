/* Marvin serial protocol between the host and the body's MCU (STM32F302R8).
 *
 * One header, shared by the firmware (C11) and the host (C++20, core/devices). The byte
 * diagrams of every frame are in firmware/PROTOCOL.md; this file is the normative code.
 *
 * Framing in one paragraph. Every byte says what it is by its top bits:
 *   10xxxxxx  lead byte of a LOCOMOTION frame (2 bytes in all)
 *   11tttttt  lead byte of an EXTENDED frame of type t (fixed length per type)
 *   0xxxxxxx  continuation byte (7 payload bits)
 *   0xFF      END: extended type 0x3F, one byte, marks "end of burst" (same as UART idle)
 * A frame is accepted only if (1) it has the length its lead byte announces, (2) its check
 * bits are right, (3) it is delimited: the next byte is a lead byte or END or the line went
 * idle, and (4) the decoder was in sync when the frame started: the previous frame was
 * well formed, or END / line idle came just before. Anything else is dropped and counted;
 * the decoder resynchronises by itself at the next END / idle or well-formed frame.
 *
 * Integrity bound. The locomotion frame has 16 bits: 10 bits of information and 6
 * integrity bits (3 marker bits + CRC-3). Of the 65536 two-byte words exactly 1024 = 2^10
 * are valid locomotion frames, so a random aligned word passes with probability 2^-6; with
 * the delimiter rule a frame ending at a given position of a random byte stream is accepted
 * with probability at most 2^-6 * 2^-1 = 2^-7 (extended frames: at most 2^-14 more). So a
 * stream of N random bytes executes at most N/128 commands on average (the sync rule makes
 * the real figure far lower; tests/firmware checks both). Every single-bit error is
 * detected (marker bits by class, data bits by the CRC), and a dropped or inserted byte
 * either truncates, lengthens or orphans a frame, which drops it and puts the decoder out
 * of sync, so the garbled neighbour frame is not executed either.
 *
 * Thread-safety: none; a decoder belongs to one reader.
 */
#ifndef MARVIN_PROTOCOL_H_
#define MARVIN_PROTOCOL_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MV_BAUD_RATE 115200u

/* Byte classes. */
#define MV_END 0xFFu
#define MV_LOCO_LEAD_MASK 0xC0u
#define MV_LOCO_LEAD_BITS 0x80u
#define MV_EXT_LEAD_BITS 0xC0u

/* Locomotion directions (the original robot's 2-bit field). Speed 0 stops that side. */
enum mv_direction {
  MV_LEFT_FORWARD = 0,
  MV_LEFT_BACKWARD = 1,
  MV_RIGHT_FORWARD = 2,
  MV_RIGHT_BACKWARD = 3
};

/* Frame types. 0 is the locomotion frame; the others are extended types (6 bits). */
enum mv_frame_type {
  MV_LOCOMOTION = 0x00,
  /* host -> MCU */
  MV_STOP_ALL = 0x01,    /* no payload */
  MV_HEAD_TILT = 0x02,   /* angle + 64 (degrees, -60..60) */
  MV_SONAR_SWEEP = 0x03, /* mode, from, to, step (degrees) */
  MV_LEDS = 0x04,        /* 7 LED bits */
  MV_CONFIG = 0x05,      /* deadman ms (14 bits), obstacle stop distance mm (14 bits) */
  MV_PING = 0x06,        /* no payload; answered by an ACK */
  /* MCU -> host */
  MV_SONAR_READING = 0x20, /* angle, flags, distance mm (14 bits), time ms (28 bits) */
  MV_ACK = 0x21,           /* acknowledged type, argument */
  MV_FAULT = 0x22,         /* code, value (14 bits), time ms (28 bits) */
  MV_STATUS = 0x23,        /* left, right (14 each: bit 8 backward, 7..0 speed), head,
                              flags, rx errors (14), time ms (28) */
  MV_END_TYPE = 0x3F       /* the END byte */
};

/* Sonar sweep modes. */
enum mv_sweep_mode { MV_SWEEP_OFF = 0, MV_SWEEP_ON = 1, MV_SWEEP_FIXED = 2 };

/* Fault codes. */
enum mv_fault_code {
  MV_FAULT_DEADMAN = 1,  /* no valid command for the deadman time: motors stopped */
  MV_FAULT_OBSTACLE = 2, /* obstacle ahead closer than the stop distance: forward stopped */
  MV_FAULT_RX_OVERFLOW = 3,
  MV_FAULT_BAD_ARGUMENT = 4 /* a well-formed frame with an out-of-range field */
};

/* LED bits of the head's 74HC595. */
#define MV_LED_RED 0x01u
#define MV_LED_GREEN 0x02u
#define MV_LED_YELLOW 0x04u

/* STATUS flag bits. */
#define MV_STATUS_SWEEPING 0x01u
#define MV_STATUS_BLOCKED 0x02u /* forward motion refused: obstacle ahead */

/* Payload sizes (7-bit continuation bytes) of the extended frames; -1 for unknown types.
 * An extended frame is: lead, payload, CRC-8 high bit, CRC-8 low 7 bits. */
int mv_ext_payload_len(uint8_t type);
/* Total frame length announced by a lead byte (2 for locomotion, 1 for END), 0 if
 * the lead byte announces an unknown type. */
size_t mv_frame_len(uint8_t lead);

#define MV_MAX_PAYLOAD 12
#define MV_MAX_FRAME (1 + MV_MAX_PAYLOAD + 2)

/* A decoded frame. For MV_LOCOMOTION, payload[0] = direction, payload[1] = speed
 * (8 bits, so not a 7-bit value); otherwise payload holds the 7-bit payload bytes. */
typedef struct mv_frame {
  uint8_t type;
  uint8_t len; /* payload bytes */
  uint8_t payload[MV_MAX_PAYLOAD];
} mv_frame;

/* CRC-3 (x^3 + x + 1, init 0b111) over the 10 locomotion information bits. */
uint8_t mv_crc3(uint16_t info10);
/* CRC-8 (x^8 + x^2 + x + 1, init 0) over bytes. */
uint8_t mv_crc8(const uint8_t* bytes, size_t n);

/* Encoders. Each writes one frame (without END) into out (MV_MAX_FRAME bytes) and returns
 * its length, or 0 if an argument is out of range (the frame cannot be built). */
size_t mv_encode_locomotion(uint8_t direction, uint8_t speed, uint8_t* out);
size_t mv_encode_ext(uint8_t type, const uint8_t* payload7, size_t n, uint8_t* out);
size_t mv_encode_frame(const mv_frame* frame, uint8_t* out);

/* 14-bit and 28-bit fields, 7 bits per byte, most significant first. */
void mv_put14(uint8_t* p, uint16_t v);
uint16_t mv_get14(const uint8_t* p);
void mv_put28(uint8_t* p, uint32_t v);
uint32_t mv_get28(const uint8_t* p);

/* The stream decoder. */
typedef struct mv_decoder {
  uint8_t buf[MV_MAX_FRAME];
  uint8_t len;      /* bytes of the frame in progress */
  uint8_t expected; /* its announced length (0: unknown type) */
  uint8_t overlong; /* more continuation bytes than announced */
  uint8_t synced;   /* the previous boundary was clean */
  uint32_t accepted;
  uint32_t rejected; /* frames or stray bytes dropped */
} mv_decoder;

void mv_decoder_init(mv_decoder* d);
/* Feeds one byte. Returns 1 and fills *out when the byte completes an accepted frame (the
 * frame before it: acceptance waits for the delimiter), else 0. */
int mv_decoder_push(mv_decoder* d, uint8_t byte, mv_frame* out);
/* The line went idle (or the reader knows the burst ended): same as receiving END. */
int mv_decoder_idle(mv_decoder* d, mv_frame* out);

#ifdef __cplusplus
}
#endif

#endif /* MARVIN_PROTOCOL_H_ */
