/* The example of docs/c-interface.md (compiled by tests/c_interface.rs, so it stays true). */
#include "rotorid.h"

static ROTORID_STORAGE(storage, ROTORID_FLIGHT_STORAGE_SIZE); /* static, 8-byte aligned */
static rotorid_ident_t *id;

int setup(void);
void at_50_hz(const rotorid_ned_frd_sample_t *px4_sample);

int setup(void) {
    rotorid_error_t err;
    /* NULL config: the flight settings; NULL sets: the default forward-speed sets */
    return rotorid_init_flight(storage, sizeof storage, NULL, NULL, &id, &err);
}

void at_50_hz(const rotorid_ned_frd_sample_t *px4_sample) {
    rotorid_sample_t s;
    rotorid_step_output_t out;
    rotorid_error_t err;
    rotorid_sample_from_ned_frd(px4_sample, &s); /* NED, FRD rad/s -> paper axes, deg/s */
    int rc = rotorid_step(id, &s, &out, &err);
    if (rc == ROTORID_E_TIME_STEP) rotorid_resume(id, &s, &out.prediction, &err); /* a gap */
    /* other codes: the sample was refused and nothing changed; count it, carry on */
}
