/* Register definitions for the STM32F302R8 (RM0365, PM0214), only what Marvin uses.
 * No vendor library is available, so these are written from the reference manual. */
#ifndef MARVIN_STM32F302_REGS_H_
#define MARVIN_STM32F302_REGS_H_

#include <stdint.h>

#define REG32(addr) (*(volatile uint32_t*)(addr))

/* Cortex-M4 core peripherals */
#define SYST_CSR REG32(0xE000E010u)
#define SYST_RVR REG32(0xE000E014u)
#define SYST_CVR REG32(0xE000E018u)
#define NVIC_ISER(n) REG32(0xE000E100u + 4u * (n))
#define NVIC_IPR_BYTE(irq) (*(volatile uint8_t*)(0xE000E400u + (irq)))
#define SCB_ICSR REG32(0xE000ED04u)
#define SCB_VTOR REG32(0xE000ED08u)
#define SCB_SHPR3 REG32(0xE000ED20u)
#define SCB_CPACR REG32(0xE000ED88u)
#define SCB_ICSR_PENDSVSET (1u << 28)

/* RCC */
#define RCC_BASE 0x40021000u
#define RCC_CR REG32(RCC_BASE + 0x00u)
#define RCC_CFGR REG32(RCC_BASE + 0x04u)
#define RCC_AHBENR REG32(RCC_BASE + 0x14u)
#define RCC_APB2ENR REG32(RCC_BASE + 0x18u)
#define RCC_APB1ENR REG32(RCC_BASE + 0x1Cu)
#define RCC_CR_HSEON (1u << 16)
#define RCC_CR_HSERDY (1u << 17)
#define RCC_CR_HSEBYP (1u << 18)
#define RCC_CR_PLLON (1u << 24)
#define RCC_CR_PLLRDY (1u << 25)
#define RCC_CFGR_SW_PLL 0x2u
#define RCC_CFGR_SWS_MASK (0x3u << 2)
#define RCC_CFGR_SWS_PLL (0x2u << 2)
#define RCC_CFGR_PPRE1_DIV2 (0x4u << 8)
#define RCC_CFGR_PLLSRC_HSE (1u << 16) /* HSE/PREDIV */
#define RCC_CFGR_PLLMUL(x) ((uint32_t)((x)-2u) << 18)
#define RCC_AHBENR_GPIOA (1u << 17)
#define RCC_AHBENR_GPIOB (1u << 18)
#define RCC_APB1ENR_TIM2 (1u << 0)
#define RCC_APB1ENR_TIM6 (1u << 4)
#define RCC_APB1ENR_USART2 (1u << 17)
#define RCC_APB2ENR_TIM15 (1u << 16)

/* FLASH */
#define FLASH_ACR REG32(0x40022000u)
#define FLASH_ACR_LATENCY_2WS 0x2u
#define FLASH_ACR_PRFTBE (1u << 4)

/* GPIO */
#define GPIOA_BASE 0x48000000u
#define GPIOB_BASE 0x48000400u
#define GPIO_MODER(b) REG32((b) + 0x00u)
#define GPIO_OSPEEDR(b) REG32((b) + 0x08u)
#define GPIO_IDR(b) REG32((b) + 0x10u)
#define GPIO_BSRR(b) REG32((b) + 0x18u)
#define GPIO_AFRL(b) REG32((b) + 0x20u)
#define GPIO_AFRH(b) REG32((b) + 0x24u)
#define GPIO_MODE_INPUT 0x0u
#define GPIO_MODE_OUTPUT 0x1u
#define GPIO_MODE_AF 0x2u

/* USART2 (new-style USART of the F3 series) */
#define USART2_BASE 0x40004400u
#define USART_CR1(b) REG32((b) + 0x00u)
#define USART_CR3(b) REG32((b) + 0x08u)
#define USART_BRR(b) REG32((b) + 0x0Cu)
#define USART_ISR(b) REG32((b) + 0x1Cu)
#define USART_ICR(b) REG32((b) + 0x20u)
#define USART_RDR(b) REG32((b) + 0x24u)
#define USART_TDR(b) REG32((b) + 0x28u)
#define USART_CR1_UE (1u << 0)
#define USART_CR1_RE (1u << 2)
#define USART_CR1_TE (1u << 3)
#define USART_CR1_IDLEIE (1u << 4)
#define USART_CR1_RXNEIE (1u << 5)
#define USART_CR1_TXEIE (1u << 7)
#define USART_ISR_ORE (1u << 3)
#define USART_ISR_IDLE (1u << 4)
#define USART_ISR_RXNE (1u << 5)
#define USART_ISR_TXE (1u << 7)
#define USART_ICR_ORECF (1u << 3)
#define USART_ICR_IDLECF (1u << 4)
#define USART2_IRQN 38u

/* General-purpose timers (TIM2 32-bit, TIM15 with break/dead-time, TIM6 basic) */
#define TIM2_BASE 0x40000000u
#define TIM6_BASE 0x40001000u
#define TIM15_BASE 0x40014000u
#define TIM_CR1(b) REG32((b) + 0x00u)
#define TIM_EGR(b) REG32((b) + 0x14u)
#define TIM_CCMR1(b) REG32((b) + 0x18u)
#define TIM_CCER(b) REG32((b) + 0x20u)
#define TIM_CNT(b) REG32((b) + 0x24u)
#define TIM_PSC(b) REG32((b) + 0x28u)
#define TIM_ARR(b) REG32((b) + 0x2Cu)
#define TIM_CCR1(b) REG32((b) + 0x34u)
#define TIM_CCR2(b) REG32((b) + 0x38u)
#define TIM_BDTR(b) REG32((b) + 0x44u)
#define TIM_CR1_CEN (1u << 0)
#define TIM_CR1_ARPE (1u << 7)
#define TIM_EGR_UG (1u << 0)
#define TIM_CCMR1_PWM1_CH1 ((0x6u << 4) | (1u << 3)) /* OC1M = PWM mode 1, OC1PE */
#define TIM_CCMR1_PWM1_CH2 ((0x6u << 12) | (1u << 11))
#define TIM_CCER_CC1E (1u << 0)
#define TIM_CCER_CC2E (1u << 4)
#define TIM_BDTR_MOE (1u << 15)

#endif /* MARVIN_STM32F302_REGS_H_ */
