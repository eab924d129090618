/* The portable firmware core. See marvin_core.h. */
#include "marvin_core.h"

#include "sonar.h"

#define HEAD_MIN_DEG (-60)
#define HEAD_MAX_DEG 60
#define OBSTACLE_FAULT_PERIOD_MS 500u
#define DEADMAN_MIN_MS 20u

void mv_config_defaults(mv_config* cfg) {
  cfg->deadman_ms = 300;
  cfg->obstacle_mm = 300;
  cfg->clearance_mm = 600;
  cfg->status_period_ms = 250;
}

static void send_ext(mv_core* core, uint8_t type, const uint8_t* payload, size_t n) {
  uint8_t out[MV_MAX_FRAME + 1];
  size_t len = mv_encode_ext(type, payload, n, out);
  if (len == 0) return;
  out[len++] = MV_END;
  core->hal->send(core->hal->ctx, out, len);
}

void mv_core_fault(mv_core* core, uint8_t code, uint16_t value, uint32_t now_ms) {
  uint8_t p[7];
  p[0] = (uint8_t)(code & 0x7Fu);
  mv_put14(&p[1], (uint16_t)(value & 0x3FFFu));
  mv_put28(&p[3], now_ms & 0x0FFFFFFFu);
  send_ext(core, MV_FAULT, p, sizeof p);
}

static void ack(mv_core* core, uint8_t type, uint8_t arg) {
  uint8_t p[2] = {type, (uint8_t)(arg & 0x7Fu)};
  send_ext(core, MV_ACK, p, sizeof p);
}

static void set_side(mv_core* core, uint8_t side, uint8_t backward, uint8_t speed) {
  core->speed[side] = speed;
  core->backward[side] = speed ? backward : 0u;
  core->hal->set_motor(core->hal->ctx, side, core->backward[side], speed);
}

static void stop_motors(mv_core* core) {
  set_side(core, 0, 0, 0);
  set_side(core, 1, 0, 0);
}

static int moving(const mv_core* core) { return core->speed[0] != 0u || core->speed[1] != 0u; }

/* Some wheel drives forwards and none backwards: the robot advances (straight or pivoting). */
static int moving_forward(const mv_core* core) {
  int any_backward = (core->speed[0] && core->backward[0]) || (core->speed[1] && core->backward[1]);
  int any_forward =
      (core->speed[0] && !core->backward[0]) || (core->speed[1] && !core->backward[1]);
  return any_forward && !any_backward;
}

static void obstacle_fault(mv_core* core, uint16_t horizontal_mm, uint32_t now_ms) {
  if (now_ms - core->last_obstacle_fault_ms >= OBSTACLE_FAULT_PERIOD_MS ||
      core->last_obstacle_fault_ms == 0u) {
    core->last_obstacle_fault_ms = now_ms ? now_ms : 1u;
    mv_core_fault(core, MV_FAULT_OBSTACLE, horizontal_mm, now_ms);
  }
}

static void send_status(mv_core* core, uint32_t now_ms) {
  uint8_t p[12];
  for (uint8_t side = 0; side < 2u; ++side)
    mv_put14(&p[2 * side], (uint16_t)((unsigned)core->backward[side] << 8 | core->speed[side]));
  p[4] = (uint8_t)(core->head_deg + 64);
  p[5] = (uint8_t)((core->sweep_mode != MV_SWEEP_OFF ? MV_STATUS_SWEEPING : 0u) |
                   (core->blocked ? MV_STATUS_BLOCKED : 0u));
  uint32_t errors = core->decoder.rejected;
  mv_put14(&p[6], (uint16_t)(errors > 0x3FFFu ? 0x3FFFu : errors));
  mv_put28(&p[8], now_ms & 0x0FFFFFFFu);
  send_ext(core, MV_STATUS, p, sizeof p);
  core->last_status_ms = now_ms;
}

/* Moves the sweep servo to a new angle; the next reading waits for it to settle. */
static void aim_sonar(mv_core* core, uint8_t angle, uint32_t now_ms) {
  core->ping_at_ms = now_ms + mv_servo_settle_ms(core->servo_deg, angle);
  core->servo_deg = angle;
  core->hal->set_sonar_servo(core->hal->ctx, angle);
}

void mv_core_init(mv_core* core, const mv_hal* hal, const mv_config* cfg, uint32_t now_ms) {
  core->hal = hal;
  if (cfg) {
    core->cfg = *cfg;
  } else {
    mv_config_defaults(&core->cfg);
  }
  mv_decoder_init(&core->decoder);
  core->head_deg = 0;
  core->leds = 0;
  core->last_command_ms = now_ms;
  core->last_status_ms = now_ms;
  core->last_obstacle_fault_ms = 0;
  core->blocked = 0;
  core->blocked_angle = 0;
  stop_motors(core);
  hal->set_head(hal->ctx, 0);
  hal->set_leds(hal->ctx, 0);
  /* Default sweep: the low arc ahead, where obstacles for the wheels are. */
  core->sweep_mode = MV_SWEEP_ON;
  core->sweep_from = 0;
  core->sweep_to = 60;
  core->sweep_step = 15;
  core->sweep_dir = 1;
  core->servo_deg = MV_SWEEP_MAX_DEG; /* unknown: assume the worst-case travel */
  aim_sonar(core, 0, now_ms);
}

static void execute_locomotion(mv_core* core, uint8_t direction, uint8_t speed, uint32_t now_ms) {
  uint8_t side = (uint8_t)(direction >> 1);
  uint8_t backward = (uint8_t)(direction & 1u);
  if (speed && backward) core->blocked = 0; /* backing or turning away: look again */
  set_side(core, side, backward, speed);
  if (core->blocked && moving_forward(core)) {
    /* An obstacle is ahead: refuse to advance (the wheel command is dropped). */
    set_side(core, side, 0, 0);
    obstacle_fault(core, 0, now_ms);
  }
}

static void execute_sweep(mv_core* core, const mv_frame* f, uint32_t now_ms) {
  uint8_t mode = f->payload[0], from = f->payload[1], to = f->payload[2], step = f->payload[3];
  if (mode > MV_SWEEP_FIXED || from > MV_SWEEP_MAX_DEG || to > MV_SWEEP_MAX_DEG || from > to ||
      (mode == MV_SWEEP_ON && step == 0u)) {
    mv_core_fault(core, MV_FAULT_BAD_ARGUMENT, MV_SONAR_SWEEP, now_ms);
    return;
  }
  core->sweep_mode = mode;
  core->sweep_from = from;
  core->sweep_to = to;
  core->sweep_step = step ? step : 1u;
  core->sweep_dir = 1;
  if (mode != MV_SWEEP_OFF) aim_sonar(core, from, now_ms);
}

void mv_core_execute(mv_core* core, const mv_frame* f, uint32_t now_ms) {
  core->last_command_ms = now_ms;
  switch (f->type) {
    case MV_LOCOMOTION:
      execute_locomotion(core, f->payload[0], f->payload[1], now_ms);
      ack(core, MV_LOCOMOTION, f->payload[0]);
      break;
    case MV_STOP_ALL:
      stop_motors(core);
      ack(core, MV_STOP_ALL, 0);
      break;
    case MV_HEAD_TILT: {
      int deg = (int)f->payload[0] - 64;
      if (deg < HEAD_MIN_DEG || deg > HEAD_MAX_DEG) {
        mv_core_fault(core, MV_FAULT_BAD_ARGUMENT, MV_HEAD_TILT, now_ms);
        break;
      }
      core->head_deg = (int8_t)deg;
      core->hal->set_head(core->hal->ctx, core->head_deg);
      ack(core, MV_HEAD_TILT, f->payload[0]);
      break;
    }
    case MV_SONAR_SWEEP:
      execute_sweep(core, f, now_ms);
      ack(core, MV_SONAR_SWEEP, f->payload[0]);
      break;
    case MV_LEDS:
      core->leds = f->payload[0];
      core->hal->set_leds(core->hal->ctx, core->leds);
      ack(core, MV_LEDS, f->payload[0]);
      break;
    case MV_CONFIG: {
      uint16_t deadman = mv_get14(&f->payload[0]);
      if (deadman < DEADMAN_MIN_MS) {
        mv_core_fault(core, MV_FAULT_BAD_ARGUMENT, MV_CONFIG, now_ms);
        break;
      }
      core->cfg.deadman_ms = deadman;
      core->cfg.obstacle_mm = mv_get14(&f->payload[2]);
      ack(core, MV_CONFIG, 0);
      break;
    }
    case MV_PING:
      ack(core, MV_PING, 0);
      break;
    default: /* telemetry types are not commands: ignore */
      break;
  }
}

void mv_core_rx(mv_core* core, uint8_t byte, uint32_t now_ms) {
  mv_frame f;
  if (mv_decoder_push(&core->decoder, byte, &f)) mv_core_execute(core, &f, now_ms);
}

void mv_core_rx_idle(mv_core* core, uint32_t now_ms) {
  mv_frame f;
  if (mv_decoder_idle(&core->decoder, &f)) mv_core_execute(core, &f, now_ms);
}

void mv_core_tick(mv_core* core, uint32_t now_ms) {
  if (moving(core) && now_ms - core->last_command_ms >= core->cfg.deadman_ms) {
    stop_motors(core);
    mv_core_fault(core, MV_FAULT_DEADMAN, core->cfg.deadman_ms, now_ms);
  }
  if (now_ms - core->last_status_ms >= core->cfg.status_period_ms) send_status(core, now_ms);
}

int mv_core_ping_due(const mv_core* core, uint32_t now_ms, uint8_t* angle_deg) {
  if (core->sweep_mode == MV_SWEEP_OFF) return 0;
  if ((int32_t)(now_ms - core->ping_at_ms) < 0) return 0;
  *angle_deg = core->servo_deg;
  return 1;
}

static void next_sweep_angle(mv_core* core, uint32_t now_ms) {
  if (core->sweep_mode == MV_SWEEP_FIXED || core->sweep_from == core->sweep_to) {
    core->ping_at_ms = now_ms;
    return;
  }
  int next = (int)core->servo_deg + core->sweep_dir * (int)core->sweep_step;
  if (next > (int)core->sweep_to || next < (int)core->sweep_from) {
    core->sweep_dir = (int8_t)-core->sweep_dir;
    next = (int)core->servo_deg + core->sweep_dir * (int)core->sweep_step;
    if (next > (int)core->sweep_to) next = core->sweep_to;
    if (next < (int)core->sweep_from) next = core->sweep_from;
  }
  aim_sonar(core, (uint8_t)next, now_ms);
}

void mv_core_echo(mv_core* core, uint32_t echo_us, uint32_t now_ms) {
  uint8_t angle = core->servo_deg;
  uint16_t d = mv_sonar_distance_mm(echo_us);
  int echo = echo_us != 0u && echo_us < MV_SONAR_ECHO_TIMEOUT_US;
  uint8_t p[8];
  p[0] = angle;
  p[1] = (uint8_t)(echo ? 0u : 1u); /* flags: 1 = no echo within 2.5 m */
  mv_put14(&p[2], d);
  mv_put28(&p[4], now_ms & 0x0FFFFFFFu);
  send_ext(core, MV_SONAR_READING, p, sizeof p);

  if (angle <= 90u && core->cfg.obstacle_mm != 0u) {
    int32_t h, v;
    mv_sonar_components(d, angle, &h, &v);
    if (echo && h < (int32_t)core->cfg.obstacle_mm && v < (int32_t)core->cfg.clearance_mm) {
      core->blocked = 1;
      core->blocked_angle = angle;
      if (moving_forward(core)) {
        stop_motors(core);
        obstacle_fault(core, (uint16_t)h, now_ms);
      }
    } else if (core->blocked && core->blocked_angle == angle) {
      core->blocked = 0;
    }
  }
  next_sweep_angle(core, now_ms);
}
