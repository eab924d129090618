/* Sonar arithmetic for the HC-SR04 on its sweep servo (portable, integer only). */
#ifndef MARVIN_SONAR_H_
#define MARVIN_SONAR_H_

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MV_SOUND_SPEED_M_S 346u /* at about 25 degC */
#define MV_SONAR_MAX_MM 2500u   /* readings are capped at 2.5 m */
/* Echo timeout: the round trip of 2.5 m, 2 * 2.5 / 346 s = 14451 us (about 69 readings/s). */
#define MV_SONAR_ECHO_TIMEOUT_US 14451u
#define MV_SONAR_TRIGGER_US 10u
/* MG996R: 0.14 s per 60 degrees. */
#define MV_SERVO_MS_PER_60_DEG 140u
#define MV_SWEEP_MAX_DEG 120u

/* D = C * T / 2 in millimetres for an echo of echo_us microseconds, capped at 2500 mm.
 * An echo of 0 or at/after the timeout means "nothing within range" and gives 2500. */
uint16_t mv_sonar_distance_mm(uint32_t echo_us);

/* Time for the sweep servo to move from one angle to another and settle, in ms (rounded
 * up): |to - from| * 140 / 60. */
uint32_t mv_servo_settle_ms(uint8_t from_deg, uint8_t to_deg);

/* Components of a reading taken at angle_deg above the horizontal (0 = straight ahead,
 * 90 = straight up, 120 = up and backwards), in the vertical plane of the heading:
 * horizontal = D * cos(theta), vertical = D * sin(theta). (The original paper gives
 * D * tan(theta) for the vertical component; that is a typo: the sonar measures the
 * hypotenuse, so the opposite side is D * sin(theta).) horizontal is negative behind the
 * robot (theta > 90). */
void mv_sonar_components(uint16_t distance_mm, uint8_t angle_deg, int32_t* horizontal_mm,
                         int32_t* vertical_mm);

/* cos(deg) * 32767 for 0..180 degrees, rounded. */
int32_t mv_cos_q15(unsigned deg);
int32_t mv_sin_q15(unsigned deg);

#ifdef __cplusplus
}
#endif

#endif /* MARVIN_SONAR_H_ */
