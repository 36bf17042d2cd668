/*
 * The smallest useful C firmware: one identifier, initialised and stepped through samples with
 * the attitude as a quaternion; nothing else of the library. Its flash is what an autopilot
 * pays for rotorid (scripts/footprint.sh measures it per kind; docs/cost.md). By default the
 * lean calls of the flight default (rotorid_lean_init_flight + rotorid_lean_step_flight: that
 * kind's init and step only, no trigonometry); ROTORID_MINIMAL_INIT / _STEP / _STORAGE choose
 * another kind or the generic calls (rotorid_init_<kind> + rotorid_step). Startup and vector
 * table are here so that nothing but the C compiler, the library and libgcc is linked. It
 * runs under QEMU mps2-an386 too (exit through semihosting; 0 when every step is accepted).
 */
#include <stdint.h>

#include "rotorid.h"

#ifndef ROTORID_MINIMAL_INIT
#define ROTORID_MINIMAL_INIT rotorid_lean_init_flight
#define ROTORID_MINIMAL_STEP rotorid_lean_step_flight
#define ROTORID_MINIMAL_STORAGE ROTORID_FLIGHT_STORAGE_SIZE
#endif
#ifndef ROTORID_MINIMAL_STEP
#define ROTORID_MINIMAL_STEP rotorid_step
#endif

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss;
extern void _stack_start(void);
int main(void);

static int semihost(int op, const void *arg) {
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

static void __attribute__((noreturn)) exit_with(int ok) {
    (void)semihost(0x18, (const void *)(uintptr_t)(ok ? 0x20026 : 0x20023));
    for (;;) {
    }
}

void Reset_Handler(void) {
    uint32_t *src = &_sidata;
    for (uint32_t *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
    for (uint32_t *dst = &_sbss; dst < &_ebss;) *dst++ = 0;
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20; /* FPU on */
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    exit_with(main() == 0);
}

void Fault_Handler(void) { exit_with(0); }

__attribute__((section(".vector_table"), used)) static void (*const vectors[16])(void) = {
    _stack_start, Reset_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, 0, 0, 0, 0, Fault_Handler, Fault_Handler, 0,
    Fault_Handler, Fault_Handler,
};

static ROTORID_STORAGE(storage, ROTORID_MINIMAL_STORAGE);

int main(void) {
    rotorid_ident_t *id = 0;
    if (ROTORID_MINIMAL_INIT(storage, sizeof storage, 0, 0, &id, 0) != ROTORID_OK) return 1;
    rotorid_sample_t s = {0};
    rotorid_step_output_t out;
    int ok = 1;
    for (uint32_t k = 0; k < 100u; k++) {
        float t = 0.02f * (float)k;
        s.time_us = 1000000u + 20000u * k;
        s.controls[0] = 0.5f;
        s.rates[0] = (float)(k % 7u) - 3.0f;
        s.velocity[0] = 0.1f * t;
        s.attitude_form = ROTORID_ATTITUDE_QUATERNION;
        s.q[0] = 1.0f;
        ok &= ROTORID_MINIMAL_STEP(id, &s, &out, 0) == ROTORID_OK;
    }
    return ok ? 0 : 1;
}
