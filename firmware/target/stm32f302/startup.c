/* Start-up code and vector table for the STM32F302R8 (Cortex-M4F). */
#include <stdint.h>

#include "stm32f302_regs.h"

extern uint32_t _estack, _sidata, _sdata, _edata, _sbss, _ebss;
int main(void);

void Reset_Handler(void);
void Default_Handler(void);
void NMI_Handler(void) __attribute__((weak, alias("Default_Handler")));
void HardFault_Handler(void) __attribute__((weak, alias("Default_Handler")));
void MemManage_Handler(void) __attribute__((weak, alias("Default_Handler")));
void BusFault_Handler(void) __attribute__((weak, alias("Default_Handler")));
void UsageFault_Handler(void) __attribute__((weak, alias("Default_Handler")));
void SVC_Handler(void) __attribute__((weak, alias("Default_Handler")));
void DebugMon_Handler(void) __attribute__((weak, alias("Default_Handler")));
void PendSV_Handler(void) __attribute__((weak, alias("Default_Handler")));
void SysTick_Handler(void) __attribute__((weak, alias("Default_Handler")));
void USART2_IRQHandler(void) __attribute__((weak, alias("Default_Handler")));

#define IRQ_COUNT 82u /* STM32F302x8: external interrupts 0..81 */

typedef void (*vector_fn)(void);

/* The table the core reads at reset: initial stack pointer, then the handlers. */
__attribute__((section(".isr_vector"), used)) static const vector_fn kVectors[16 + IRQ_COUNT] = {
    [0] = (vector_fn)(uintptr_t)&_estack,
    [1] = Reset_Handler,
    [2] = NMI_Handler,
    [3] = HardFault_Handler,
    [4] = MemManage_Handler,
    [5] = BusFault_Handler,
    [6] = UsageFault_Handler,
    [11] = SVC_Handler,
    [12] = DebugMon_Handler,
    [14] = PendSV_Handler,
    [15] = SysTick_Handler,
    [16 + USART2_IRQN] = USART2_IRQHandler,
};

void Reset_Handler(void) {
  /* The FPU first: the code is built for the hard-float ABI. */
  SCB_CPACR |= (0xFu << 20);
  __asm volatile("dsb\n\tisb");
  uint32_t* src = &_sidata;
  for (uint32_t* dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0u;
  main();
  for (;;) {
  }
}

/* Faults and unexpected interrupts end here. The wheels must not keep turning: switch the
 * motor PWM outputs off (TIM15 main output enable; the L293D's enables then read low),
 * then hang until a reset. */
void Default_Handler(void) {
  TIM_BDTR(TIM15_BASE) = 0u;
  for (;;) {
  }
}
