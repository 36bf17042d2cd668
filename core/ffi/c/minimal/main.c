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

#ifdef ROTORID_MINIMAL_COUNT
/* Instructions per step under QEMU -icount shift=0: SysTick on the core clock (25 MHz in the
 * mps2-an386 model) counts one tick per 40 instructions. Its 24-bit count falls. */
#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
static uint32_t ticks_sum, ticks_max, steps_timed;
static uint32_t fnv = 2166136261u; /* FNV-1a of every step's prediction and innovation bits */

static void hash_bytes(const void *data, uint32_t n) {
    const unsigned char *b = data;
    for (uint32_t i = 0; i < n; i++) fnv = (fnv ^ b[i]) * 16777619u;
}

static void put_u32(char **p, uint32_t v) {
    char digits[10];
    int n = 0;
    do {
        digits[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v);
    while (n) *(*p)++ = digits[--n];
}

static void report(void) {
    char line[96], *p = line;
    const char *a = "rotorid-minimal: steps ", *b = " ticks ", *c = " max ", *d = " fnv ";
    while (*a) *p++ = *a++;
    put_u32(&p, steps_timed);
    while (*b) *p++ = *b++;
    put_u32(&p, ticks_sum);
    while (*c) *p++ = *c++;
    put_u32(&p, ticks_max);
    while (*d) *p++ = *d++;
    put_u32(&p, fnv);
    *p++ = '\n';
    *p = 0;
    (void)semihost(0x04, line); /* SYS_WRITE0 */
}
#endif

int main(void) {
    rotorid_ident_t *id = 0;
    if (ROTORID_MINIMAL_INIT(storage, sizeof storage, 0, 0, &id, 0) != ROTORID_OK) return 1;
#ifdef ROTORID_MINIMAL_COUNT
    SYST_RVR = 0xFFFFFFu;
    SYST_CVR = 0u;
    SYST_CSR = 5u; /* enabled, core clock, no interrupt */
#endif
    rotorid_sample_t s = {0};
    rotorid_step_output_t out;
    int ok = 1;
    for (uint32_t k = 0; k < 200u; k++) {
        /* Forward and sideways speed a triangle of 0..10 m/s (period 2 s), so that every
         * speed rule of the flight kind fires and learns; the roll rate steps through ±3 rad/s. */
        uint32_t phase = k % 100u;
        float speed = 0.2f * (float)(phase < 50u ? phase : 100u - phase);
        s.time_us = 1000000u + 20000u * k;
        s.controls[0] = 0.5f;
        s.rates[0] = (float)(k % 7u) - 3.0f;
        s.velocity[0] = speed;
        s.velocity[2] = speed;
        s.attitude_form = ROTORID_ATTITUDE_QUATERNION;
        s.q[0] = 1.0f;
#ifdef ROTORID_MINIMAL_COUNT
        uint32_t before = SYST_CVR;
#endif
        ok &= ROTORID_MINIMAL_STEP(id, &s, &out, 0) == ROTORID_OK;
#ifdef ROTORID_MINIMAL_COUNT
        uint32_t ticks = (before - SYST_CVR) & 0xFFFFFFu;
        hash_bytes(&out.prediction, sizeof out.prediction);
        hash_bytes(&out.innovation, sizeof out.innovation);
        if (k >= 100u) { /* every rule has fired by then */
            ticks_sum += ticks;
            if (ticks > ticks_max) ticks_max = ticks;
            steps_timed++;
        }
#endif
    }
#ifdef ROTORID_MINIMAL_COUNT
    report();
#endif
    return ok ? 0 : 1;
}
