/* Steps a flight identifier through one second at 50 Hz, saves and restores what it learnt. */
#include <stdint.h>

#include "rotorid.h"

static ROTORID_STORAGE(storage, ROTORID_FLIGHT_STORAGE_SIZE); /* 8-byte aligned */
static uint8_t saved[ROTORID_FLIGHT_EXPORT_SIZE];

int main(void) {
    rotorid_ident_t *id = NULL;
    rotorid_error_t err;
    rotorid_sample_t s = {0};
    rotorid_step_output_t out;
    size_t len = 0;
    int32_t rc = rotorid_init_flight(storage, sizeof storage, NULL, NULL, &id, &err);
    if (rc != ROTORID_OK) return 1;
    for (uint32_t k = 0; k < 50u; k++) {
        s.time_us = 1000000u + 20000u * k;
        s.controls[0] = 0.5f;                      /* collective */
        s.rates[0] = (float)(k % 5u) - 2.0f;       /* q, deg/s */
        rc = rotorid_step(id, &s, &out, &err);
        if (rc == ROTORID_E_TIME_STEP) rc = rotorid_resume(id, &s, &out.prediction, &err);
        if (rc != ROTORID_OK) return 2;            /* the sample was refused: nothing changed */
    }
    rc = rotorid_export(id, saved, sizeof saved, &len, &err);
    if (rc != ROTORID_OK || len != ROTORID_FLIGHT_EXPORT_SIZE) return 3;
    rc = rotorid_import(id, saved, len, &err);     /* e.g. at the next boot */
    return rc == ROTORID_OK ? 0 : 4;
}
