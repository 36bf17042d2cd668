/*
 * A host program that prepares an identifier with the lean init only and checks what the
 * generic calls do with it (tests/c_interface.rs runs it): they refuse it (NOT_INITIALISED,
 * nothing written) as long as no full init of the kind ran in the program, the lean step and
 * resume take it, and once a full init of the kind ran elsewhere the generic calls take it
 * too. Exit status 0 when every check holds; the failed check's line on stderr otherwise.
 */
#include <stdio.h>
#include <string.h>

#include "rotorid.h"

static ROTORID_STORAGE(lean_storage, ROTORID_FLIGHT_STORAGE_SIZE);
static ROTORID_STORAGE(full_storage, ROTORID_FLIGHT_STORAGE_SIZE);
static uint8_t exported[ROTORID_FLIGHT_EXPORT_SIZE];

#define CHECK(cond)                                                  \
    do {                                                             \
        if (!(cond)) {                                               \
            fprintf(stderr, "lean_only.c:%d: %s\n", __LINE__, #cond); \
            return 1;                                                \
        }                                                            \
    } while (0)

static void sample_at(uint32_t k, rotorid_sample_t *s) {
    memset(s, 0, sizeof *s);
    s->time_us = 1000000u + 20000u * (uint64_t)k;
    s->controls[0] = 0.5f;
    s->rates[0] = (float)(k % 7u) - 3.0f;
    s->velocity[0] = 0.002f * (float)k;
    s->attitude_form = ROTORID_ATTITUDE_QUATERNION;
    s->q[0] = 1.0f;
}

int main(void) {
    rotorid_ident_t *lean = NULL, *full = NULL;
    rotorid_sample_t s;
    rotorid_step_output_t out, untouched;
    rotorid_state_t state;
    rotorid_error_t err;
    size_t n = 0;
    uint32_t kind = 0;

    CHECK(rotorid_lean_init_flight(lean_storage, sizeof lean_storage, NULL, NULL, &lean, &err) ==
          ROTORID_OK);
    sample_at(0, &s);
    CHECK(rotorid_lean_step_flight(lean, &s, &out, &err) == ROTORID_OK);

    /* No full init of the flight kind yet: every generic call refuses the storage. */
    memset(&out, 0x5a, sizeof out);
    untouched = out;
    sample_at(1, &s);
    CHECK(rotorid_step(lean, &s, &out, &err) == ROTORID_E_NOT_INITIALISED);
    CHECK(memcmp(&out, &untouched, sizeof out) == 0);
    CHECK(rotorid_resume(lean, &s, &state, &err) == ROTORID_E_NOT_INITIALISED);
    CHECK(rotorid_export(lean, exported, sizeof exported, &n, &err) == ROTORID_E_NOT_INITIALISED);
    CHECK(n == 0);
    CHECK(rotorid_info(lean, &kind, NULL, &err) == ROTORID_E_NOT_INITIALISED);
    CHECK(kind == 0);

    /* The lean calls carry on; a gap is a TIME_STEP that the lean resume restarts from. */
    CHECK(rotorid_lean_step_flight(lean, &s, &out, &err) == ROTORID_OK);
    sample_at(100, &s);
    CHECK(rotorid_lean_step_flight(lean, &s, &out, &err) == ROTORID_E_TIME_STEP);
    CHECK(rotorid_lean_resume_flight(lean, &s, &state, &err) == ROTORID_OK);

    /* A full init of the kind elsewhere registers its view: the generic calls now take the
     * lean storage too, and the lean calls take the full one. */
    CHECK(rotorid_init_flight(full_storage, sizeof full_storage, NULL, NULL, &full, &err) ==
          ROTORID_OK);
    CHECK(rotorid_export(lean, exported, sizeof exported, &n, &err) == ROTORID_OK);
    CHECK(n == ROTORID_FLIGHT_EXPORT_SIZE);
    CHECK(rotorid_info(lean, &kind, NULL, &err) == ROTORID_OK && kind == ROTORID_KIND_FLIGHT);
    sample_at(0, &s);
    CHECK(rotorid_lean_step_flight(full, &s, &out, &err) == ROTORID_OK);
    return 0;
}
