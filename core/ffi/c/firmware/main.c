/*
 * A bare-metal C firmware for QEMU's mps2-an386 (Cortex-M4F) that links the thumbv7em static
 * library of the C interface and runs the shared driver (../drive.c): its report goes out over
 * semihosting and its result is the exit code. Startup, vector table and semihosting are here
 * so that nothing but the C compiler and the library is needed (no vendor SDK, no libc).
 */
#include <stdint.h>

#include "../drive.h"

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss;
/* The initial stack pointer (link.ld). Declared as a function only so that it can stand in the
 * vector table, an array of function pointers, without a non-ISO cast. */
extern void _stack_start(void);
int main(void);

/* Semihosting (ARM DUI 0471): `bkpt 0xAB` with the operation in r0 and its argument in r1. */
static int semihost(int op, const void *arg) {
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

enum { SYS_WRITE0 = 0x04, SYS_EXIT = 0x18 };
enum { ADP_APPLICATION_EXIT = 0x20026, ADP_RUNTIME_ERROR = 0x20023 };

static void emit(const char *line) { (void)semihost(SYS_WRITE0, line); }

static void __attribute__((noreturn)) exit_with(int ok) {
    (void)semihost(SYS_EXIT, (const void *)(uintptr_t)(ok ? ADP_APPLICATION_EXIT : ADP_RUNTIME_ERROR));
    for (;;) {
    }
}

void Reset_Handler(void) {
    /* .data from flash, .bss zeroed, then the FPU on (CP10 and CP11 full access). */
    uint32_t *src = &_sidata;
    for (uint32_t *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
    for (uint32_t *dst = &_sbss; dst < &_ebss;) *dst++ = 0;
    *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    exit_with(main() == 0);
}

/* Any fault ends the run with a failure instead of hanging QEMU. */
void Fault_Handler(void) {
    emit("FAIL fault\n");
    exit_with(0);
}

__attribute__((section(".vector_table"), used)) static void (*const vectors[16])(void) = {
    _stack_start, Reset_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, 0, 0, 0, 0, Fault_Handler, Fault_Handler, 0,
    Fault_Handler, Fault_Handler,
};

/* Stack painting: the deepest the stack went, reported as a "stack" line (bytes). */
#define PAINT 0x5AA5F00Du

static char *put_dec(char *at, uint32_t v) {
    char tmp[10];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n) *at++ = tmp[--n];
    return at;
}

int main(void) {
    uint32_t *p = &_ebss;
    uint32_t here;
    /* Paint from the end of .bss to a little below this frame. */
    while (p + 64 < &here) *p++ = PAINT;
    int rc = drive(emit);
    p = &_ebss;
    while (*p == PAINT) p++;
    char line[32] = "stack ";
    char *at = put_dec(line + 6, (uint32_t)((uintptr_t)&_stack_start - (uintptr_t)p));
    at[0] = '\n';
    at[1] = 0;
    emit(line);
    return rc;
}
