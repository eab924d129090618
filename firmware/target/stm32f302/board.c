/* The STM32F302R8 target layer (Nucleo-F302R8): clocks, UART with interrupt-driven ring
 * buffers, PWM for the L293D and the two servos, HC-SR04 timing, 74HC595 LEDs. Written
 * against the registers (stm32f302_regs.h); no vendor library.
 *
 * Pins: USART2 PA2 TX / PA3 RX (ST-LINK virtual COM port), head servo PA0 (TIM2_CH1),
 * sonar servo PA1 (TIM2_CH2), L293D EN1/EN2 PB14/PB15 (TIM15_CH1/CH2, 20 kHz), IN1/IN2
 * PB0/PB1 (left), IN3/IN4 PB2/PB10 (right), HC-SR04 trigger PA8 / echo PA9 (5 V tolerant),
 * 74HC595 SER PB5 / SRCLK PB6 / RCLK PB7.
 *
 * Priorities: USART2 at 0 only moves bytes between the UART and the rings and pends PendSV.
 * PendSV (decode and execute commands: immediately, at high priority) and SysTick (1 ms
 * tick: deadman, sweep, status) share level 4, so they never preempt each other; the main
 * loop takes sonar readings and calls the core with BASEPRI raised to level 4.
 */
#include <stdint.h>

#include "../../core/marvin_core.h"
#include "../../core/sonar.h"
#include "stm32f302_regs.h"

#define CORE_PRIORITY 0x40u /* level 4 of 16 (upper nibble) */

static uint32_t g_sysclk = 8000000u;
static volatile uint32_t g_ms;
static mv_core g_core;

/* RX ring: bytes, or RX_IDLE when the line went idle. Written by USART2, read by PendSV. */
#define RX_IDLE 0x100u
#define RX_SIZE 64u
static volatile uint16_t g_rx[RX_SIZE];
static volatile uint8_t g_rx_head, g_rx_tail;
static volatile uint16_t g_rx_overflows;
/* TX ring: written by the core, read by USART2. */
#define TX_SIZE 256u
static volatile uint8_t g_tx[TX_SIZE];
static volatile uint8_t g_tx_head, g_tx_tail;

static inline void set_basepri(uint32_t level) {
  __asm volatile("msr basepri, %0" ::"r"(level) : "memory");
}

static void gpio_mode(uint32_t base, unsigned pin, uint32_t mode) {
  GPIO_MODER(base) = (GPIO_MODER(base) & ~(3u << (2u * pin))) | (mode << (2u * pin));
}
static void gpio_af(uint32_t base, unsigned pin, uint32_t af) {
  gpio_mode(base, pin, GPIO_MODE_AF);
  if (pin < 8u) {
    GPIO_AFRL(base) = (GPIO_AFRL(base) & ~(0xFu << (4u * pin))) | (af << (4u * pin));
  } else {
    GPIO_AFRH(base) = (GPIO_AFRH(base) & ~(0xFu << (4u * (pin - 8u)))) | (af << (4u * (pin - 8u)));
  }
}
static void gpio_write(uint32_t base, unsigned pin, unsigned high) {
  GPIO_BSRR(base) = high ? (1u << pin) : (1u << (pin + 16u));
}

static void clock_init(void) {
  /* HSE bypass (8 MHz from the ST-LINK's MCO) x 9 = 72 MHz; HSI/2 x 16 = 64 MHz if absent. */
  FLASH_ACR = FLASH_ACR_LATENCY_2WS | FLASH_ACR_PRFTBE;
  RCC_CR |= RCC_CR_HSEBYP | RCC_CR_HSEON;
  uint32_t timeout = 100000u;
  while (!(RCC_CR & RCC_CR_HSERDY) && --timeout) {
  }
  if (timeout) {
    RCC_CFGR = RCC_CFGR_PLLSRC_HSE | RCC_CFGR_PLLMUL(9u) | RCC_CFGR_PPRE1_DIV2;
    g_sysclk = 72000000u;
  } else {
    RCC_CR &= ~(RCC_CR_HSEON | RCC_CR_HSEBYP);
    RCC_CFGR = RCC_CFGR_PLLMUL(16u) | RCC_CFGR_PPRE1_DIV2;
    g_sysclk = 64000000u;
  }
  RCC_CR |= RCC_CR_PLLON;
  while (!(RCC_CR & RCC_CR_PLLRDY)) {
  }
  RCC_CFGR |= RCC_CFGR_SW_PLL;
  while ((RCC_CFGR & RCC_CFGR_SWS_MASK) != RCC_CFGR_SWS_PLL) {
  }
}

/* ---- mv_hal ---- */

static uint32_t servo_pulse_us(int degrees_0_180) {
  return 500u + (uint32_t)degrees_0_180 * 2000u / 180u;
}

static void hal_set_motor(void* ctx, uint8_t side, uint8_t backward, uint8_t speed) {
  (void)ctx;
  uint32_t duty = (TIM_ARR(TIM15_BASE) + 1u) * speed / 255u;
  unsigned in_a = side ? 2u : 0u, in_b = side ? 10u : 1u;
  gpio_write(GPIOB_BASE, in_a, speed && !backward);
  gpio_write(GPIOB_BASE, in_b, speed && backward);
  if (side) {
    TIM_CCR2(TIM15_BASE) = duty;
  } else {
    TIM_CCR1(TIM15_BASE) = duty;
  }
}
static void hal_set_head(void* ctx, int8_t degrees) {
  (void)ctx;
  TIM_CCR1(TIM2_BASE) = servo_pulse_us(90 + degrees);
}
static void hal_set_sonar_servo(void* ctx, uint8_t degrees) {
  (void)ctx;
  TIM_CCR2(TIM2_BASE) = servo_pulse_us(degrees);
}
static void hal_set_leds(void* ctx, uint8_t bits) {
  (void)ctx;
  for (int i = 7; i >= 0; --i) { /* 74HC595: shift MSB first, then latch */
    gpio_write(GPIOB_BASE, 5u, (bits >> i) & 1u);
    gpio_write(GPIOB_BASE, 6u, 1u);
    gpio_write(GPIOB_BASE, 6u, 0u);
  }
  gpio_write(GPIOB_BASE, 7u, 1u);
  gpio_write(GPIOB_BASE, 7u, 0u);
}
static void hal_send(void* ctx, const uint8_t* bytes, size_t n) {
  (void)ctx;
  uint8_t head = g_tx_head;
  if ((uint8_t)(head - g_tx_tail) > (uint8_t)(TX_SIZE - 1u - n)) return; /* full: drop */
  for (size_t i = 0; i < n; ++i) g_tx[(uint8_t)(head + i)] = bytes[i];
  g_tx_head = (uint8_t)(head + n);
  USART_CR1(USART2_BASE) |= USART_CR1_TXEIE;
}

static const mv_hal kHal = {0,       hal_set_motor, hal_set_head, hal_set_sonar_servo, hal_set_leds,
                            hal_send};

/* ---- peripherals ---- */

static void peripherals_init(void) {
  RCC_AHBENR |= RCC_AHBENR_GPIOA | RCC_AHBENR_GPIOB;
  RCC_APB1ENR |= RCC_APB1ENR_TIM2 | RCC_APB1ENR_TIM6 | RCC_APB1ENR_USART2;
  RCC_APB2ENR |= RCC_APB2ENR_TIM15;

  gpio_af(GPIOA_BASE, 2u, 7u);  /* USART2 TX */
  gpio_af(GPIOA_BASE, 3u, 7u);  /* USART2 RX */
  gpio_af(GPIOA_BASE, 0u, 1u);  /* TIM2_CH1 head servo */
  gpio_af(GPIOA_BASE, 1u, 1u);  /* TIM2_CH2 sonar servo */
  gpio_af(GPIOB_BASE, 14u, 1u); /* TIM15_CH1 left enable */
  gpio_af(GPIOB_BASE, 15u, 1u); /* TIM15_CH2 right enable */
  static const unsigned kOutB[] = {0u, 1u, 2u, 10u, 5u, 6u, 7u};
  for (unsigned i = 0; i < sizeof kOutB / sizeof kOutB[0]; ++i) {
    gpio_write(GPIOB_BASE, kOutB[i], 0u);
    gpio_mode(GPIOB_BASE, kOutB[i], GPIO_MODE_OUTPUT);
  }
  gpio_write(GPIOA_BASE, 8u, 0u);
  gpio_mode(GPIOA_BASE, 8u, GPIO_MODE_OUTPUT); /* sonar trigger */
  gpio_mode(GPIOA_BASE, 9u, GPIO_MODE_INPUT);  /* sonar echo */

  /* Timer clocks run at the system clock (APB1 /2 doubles back, APB2 /1). */
  TIM_PSC(TIM2_BASE) = g_sysclk / 1000000u - 1u; /* 1 us */
  TIM_ARR(TIM2_BASE) = 20000u - 1u;              /* 50 Hz servo frame */
  TIM_CCMR1(TIM2_BASE) = TIM_CCMR1_PWM1_CH1 | TIM_CCMR1_PWM1_CH2;
  TIM_CCR1(TIM2_BASE) = servo_pulse_us(90);
  TIM_CCR2(TIM2_BASE) = servo_pulse_us(0);
  TIM_CCER(TIM2_BASE) = TIM_CCER_CC1E | TIM_CCER_CC2E;
  TIM_EGR(TIM2_BASE) = TIM_EGR_UG;
  TIM_CR1(TIM2_BASE) = TIM_CR1_ARPE | TIM_CR1_CEN;

  TIM_PSC(TIM15_BASE) = 0u;
  TIM_ARR(TIM15_BASE) = g_sysclk / 20000u - 1u; /* 20 kHz, above hearing */
  TIM_CCMR1(TIM15_BASE) = TIM_CCMR1_PWM1_CH1 | TIM_CCMR1_PWM1_CH2;
  TIM_CCER(TIM15_BASE) = TIM_CCER_CC1E | TIM_CCER_CC2E;
  TIM_BDTR(TIM15_BASE) = TIM_BDTR_MOE;
  TIM_EGR(TIM15_BASE) = TIM_EGR_UG;
  TIM_CR1(TIM15_BASE) = TIM_CR1_ARPE | TIM_CR1_CEN;

  TIM_PSC(TIM6_BASE) = g_sysclk / 1000000u - 1u; /* free-running 1 us counter for the echo */
  TIM_ARR(TIM6_BASE) = 0xFFFFu;
  TIM_EGR(TIM6_BASE) = TIM_EGR_UG;
  TIM_CR1(TIM6_BASE) = TIM_CR1_CEN;

  USART_BRR(USART2_BASE) = (g_sysclk / 2u + MV_BAUD_RATE / 2u) / MV_BAUD_RATE; /* PCLK1 */
}

/* Interrupts last: the handlers call the core, which must be initialised. */
static void interrupts_init(void) {
  USART_CR1(USART2_BASE) =
      USART_CR1_UE | USART_CR1_RE | USART_CR1_TE | USART_CR1_RXNEIE | USART_CR1_IDLEIE;
  NVIC_IPR_BYTE(USART2_IRQN) = 0x00u;
  NVIC_ISER(USART2_IRQN / 32u) = 1u << (USART2_IRQN % 32u);
  /* PendSV (bits 23:16) and SysTick (31:24) at the core's level. */
  SCB_SHPR3 = (SCB_SHPR3 & 0x0000FFFFu) | (CORE_PRIORITY << 16) | (CORE_PRIORITY << 24);
  SYST_RVR = g_sysclk / 1000u - 1u;
  SYST_CVR = 0u;
  SYST_CSR = 0x7u; /* processor clock, interrupt, enable */
}

/* ---- interrupts ---- */

void USART2_IRQHandler(void) {
  uint32_t isr = USART_ISR(USART2_BASE);
  if (isr & USART_ISR_ORE) {
    USART_ICR(USART2_BASE) = USART_ICR_ORECF;
    g_rx_overflows++;
  }
  if (isr & (USART_ISR_RXNE | USART_ISR_IDLE)) {
    uint16_t item;
    if (isr & USART_ISR_RXNE) {
      item = (uint16_t)(USART_RDR(USART2_BASE) & 0xFFu);
    } else {
      USART_ICR(USART2_BASE) = USART_ICR_IDLECF;
      item = RX_IDLE;
    }
    if ((uint8_t)(g_rx_head - g_rx_tail) < RX_SIZE) {
      g_rx[g_rx_head % RX_SIZE] = item;
      g_rx_head = (uint8_t)(g_rx_head + 1u);
    } else {
      g_rx_overflows++;
    }
    SCB_ICSR = SCB_ICSR_PENDSVSET;
  }
  if ((isr & USART_ISR_TXE) && (USART_CR1(USART2_BASE) & USART_CR1_TXEIE)) {
    if (g_tx_tail != g_tx_head) {
      USART_TDR(USART2_BASE) = g_tx[g_tx_tail];
      g_tx_tail = (uint8_t)(g_tx_tail + 1u);
    } else {
      USART_CR1(USART2_BASE) &= ~USART_CR1_TXEIE;
    }
  }
}

/* Commands execute here, right after the bytes arrive, at the core's (high) priority. */
void PendSV_Handler(void) {
  static uint16_t reported_overflows;
  while (g_rx_tail != g_rx_head) {
    uint16_t item = g_rx[g_rx_tail % RX_SIZE];
    g_rx_tail = (uint8_t)(g_rx_tail + 1u);
    if (item == RX_IDLE) {
      mv_core_rx_idle(&g_core, g_ms);
    } else {
      mv_core_rx(&g_core, (uint8_t)item, g_ms);
    }
  }
  uint16_t overflows = g_rx_overflows;
  if (overflows != reported_overflows) {
    reported_overflows = overflows;
    mv_core_fault(&g_core, MV_FAULT_RX_OVERFLOW, (uint16_t)(overflows & 0x3FFFu), g_ms);
  }
}

void SysTick_Handler(void) {
  g_ms = g_ms + 1u;
  mv_core_tick(&g_core, g_ms);
}

/* ---- sonar ---- */

static uint16_t us_since(uint16_t start) { return (uint16_t)(TIM_CNT(TIM6_BASE) - start); }

/* One HC-SR04 reading: 10 us trigger, then the echo pulse width in us (0 = no echo within
 * the 14.5 ms timeout). Busy-waits on the 1 us counter; interrupts that hit during the
 * echo can lengthen it by a few us (a few mm), which the host's filter absorbs. */
static uint32_t sonar_measure(void) {
  uint16_t t0 = (uint16_t)TIM_CNT(TIM6_BASE);
  gpio_write(GPIOA_BASE, 8u, 1u);
  while (us_since(t0) < MV_SONAR_TRIGGER_US) {
  }
  gpio_write(GPIOA_BASE, 8u, 0u);
  t0 = (uint16_t)TIM_CNT(TIM6_BASE);
  while (!(GPIO_IDR(GPIOA_BASE) & (1u << 9))) { /* the burst takes ~0.5 ms to leave */
    if (us_since(t0) > 5000u) return 0u;
  }
  uint16_t rise = (uint16_t)TIM_CNT(TIM6_BASE);
  while (GPIO_IDR(GPIOA_BASE) & (1u << 9)) {
    if (us_since(rise) >= MV_SONAR_ECHO_TIMEOUT_US) return 0u;
  }
  return us_since(rise);
}

int main(void) {
  clock_init();
  peripherals_init();
  mv_core_init(&g_core, &kHal, 0, 0u);
  interrupts_init();
  for (;;) {
    uint8_t angle;
    set_basepri(CORE_PRIORITY);
    int due = mv_core_ping_due(&g_core, g_ms, &angle);
    set_basepri(0u);
    if (due) {
      uint32_t echo_us = sonar_measure();
      set_basepri(CORE_PRIORITY);
      mv_core_echo(&g_core, echo_us, g_ms);
      set_basepri(0u);
    } else {
      __asm volatile("wfi");
    }
  }
}
