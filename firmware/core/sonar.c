/* Sonar arithmetic: see sonar.h. Integer only, so the firmware needs no libm. */
#include "sonar.h"

/* cos(d) * 32767, d = 0..90 degrees. */
static const int16_t kCosQ15[91] = {
    32767, 32762, 32747, 32722, 32687, 32642, 32587, 32523, 32448, 32364, 32269, 32165, 32051,
    31927, 31794, 31650, 31498, 31335, 31163, 30982, 30791, 30591, 30381, 30162, 29934, 29697,
    29451, 29196, 28932, 28659, 28377, 28087, 27788, 27481, 27165, 26841, 26509, 26169, 25821,
    25465, 25101, 24730, 24351, 23964, 23571, 23170, 22762, 22347, 21925, 21497, 21062, 20621,
    20173, 19720, 19260, 18794, 18323, 17846, 17364, 16876, 16384, 15886, 15383, 14876, 14364,
    13848, 13328, 12803, 12275, 11743, 11207, 10668, 10126, 9580,  9032,  8481,  7927,  7371,
    6813,  6252,  5690,  5126,  4560,  3993,  3425,  2856,  2286,  1715,  1144,  572,   0,
};

int32_t mv_cos_q15(unsigned deg) {
  if (deg > 180u) deg = 180u;
  return deg <= 90u ? kCosQ15[deg] : -(int32_t)kCosQ15[180u - deg];
}

int32_t mv_sin_q15(unsigned deg) {
  if (deg > 180u) deg = 180u;
  return deg <= 90u ? kCosQ15[90u - deg] : kCosQ15[deg - 90u];
}

uint16_t mv_sonar_distance_mm(uint32_t echo_us) {
  if (echo_us == 0u || echo_us >= MV_SONAR_ECHO_TIMEOUT_US) return MV_SONAR_MAX_MM;
  /* mm = us * 346 [m/s] / 2 / 1000 = us * 173 / 1000, rounded */
  uint32_t mm = (echo_us * (MV_SOUND_SPEED_M_S / 2u) + 500u) / 1000u;
  return (uint16_t)(mm > MV_SONAR_MAX_MM ? MV_SONAR_MAX_MM : mm);
}

uint32_t mv_servo_settle_ms(uint8_t from_deg, uint8_t to_deg) {
  uint32_t delta =
      from_deg > to_deg ? (uint32_t)(from_deg - to_deg) : (uint32_t)(to_deg - from_deg);
  return (delta * MV_SERVO_MS_PER_60_DEG + 59u) / 60u;
}

/* x / 32767 rounded to nearest, for either sign. */
static int32_t from_q15(int32_t x) { return x >= 0 ? (x + 16383) / 32767 : (x - 16383) / 32767; }

void mv_sonar_components(uint16_t distance_mm, uint8_t angle_deg, int32_t* horizontal_mm,
                         int32_t* vertical_mm) {
  /* Correct trigonometry: horizontal = D cos(theta), vertical = D sin(theta). The paper's
   * D tan(theta) is a typo. */
  *horizontal_mm = from_q15((int32_t)distance_mm * mv_cos_q15(angle_deg));
  *vertical_mm = from_q15((int32_t)distance_mm * mv_sin_q15(angle_deg));
}
