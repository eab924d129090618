/* The portable firmware core: protocol, command execution, safety, sonar scheduling.
 *
 * No hardware access: the target layer (firmware/target/stm32f302) or the fake layer
 * (host tests, marvin-mcu-sim) gives it a mv_hal and calls it with the current time in
 * milliseconds (a free-running counter; wrap-around is handled by unsigned differences).
 *
 * Calls: mv_core_rx() for every received byte (and mv_core_rx_idle() when the UART line
 * goes idle), mv_core_tick() at least every few ms, and, whenever mv_core_ping_due() says
 * so, one sonar measurement reported with mv_core_echo(). Not reentrant: the caller makes
 * sure no two of these run at the same time (on the MCU they run at one interrupt
 * priority, or with interrupts masked).
 */
#ifndef MARVIN_CORE_H_
#define MARVIN_CORE_H_

#include <stddef.h>
#include <stdint.h>

#include "../protocol/marvin_protocol.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the core needs from the body. Every function must be set. */
typedef struct mv_hal {
  void* ctx;
  /* side 0 = left, 1 = right; speed 0 stops that side. */
  void (*set_motor)(void* ctx, uint8_t side, uint8_t backward, uint8_t speed);
  void (*set_head)(void* ctx, int8_t degrees);         /* -60..60, 0 = level */
  void (*set_sonar_servo)(void* ctx, uint8_t degrees); /* 0..120 */
  void (*set_leds)(void* ctx, uint8_t bits);
  void (*send)(void* ctx, const uint8_t* bytes, size_t n); /* one frame + END */
} mv_hal;

typedef struct mv_config {
  uint16_t deadman_ms;       /* motors stop without a valid command for this long; 300 */
  uint16_t obstacle_mm;      /* forward stops at an obstacle closer than this; 300; 0 = off */
  uint16_t clearance_mm;     /* echoes higher than this above the sonar are no obstacle; 600 */
  uint16_t status_period_ms; /* STATUS telemetry period; 250 */
} mv_config;

void mv_config_defaults(mv_config* cfg);

typedef struct mv_core {
  const mv_hal* hal;
  mv_config cfg;
  mv_decoder decoder;
  uint8_t speed[2];
  uint8_t backward[2];
  int8_t head_deg;
  uint8_t leds;
  uint32_t last_command_ms;
  uint32_t last_status_ms;
  uint32_t last_obstacle_fault_ms;
  /* sonar */
  uint8_t sweep_mode, sweep_from, sweep_to, sweep_step;
  uint8_t servo_deg;
  int8_t sweep_dir;
  uint32_t ping_at_ms; /* servo settled at this time */
  uint8_t blocked, blocked_angle;
} mv_core;

void mv_core_init(mv_core* core, const mv_hal* hal, const mv_config* cfg, uint32_t now_ms);
void mv_core_rx(mv_core* core, uint8_t byte, uint32_t now_ms);
void mv_core_rx_idle(mv_core* core, uint32_t now_ms);
void mv_core_tick(mv_core* core, uint32_t now_ms);
/* 1 if a sonar reading should be taken now at *angle_deg (the servo has settled). */
int mv_core_ping_due(const mv_core* core, uint32_t now_ms, uint8_t* angle_deg);
/* The echo of the reading mv_core_ping_due() asked for: its width in us (0 = none). */
void mv_core_echo(mv_core* core, uint32_t echo_us, uint32_t now_ms);
/* Reports a fault found by the target layer (e.g. MV_FAULT_RX_OVERFLOW). */
void mv_core_fault(mv_core* core, uint8_t code, uint16_t value, uint32_t now_ms);
/* Executes one decoded frame (exposed for tests). */
void mv_core_execute(mv_core* core, const mv_frame* frame, uint32_t now_ms);

#ifdef __cplusplus
}
#endif

#endif /* MARVIN_CORE_H_ */
