/* The C interface's exports of every kind after one stream of samples: the reference the
 * Python package's exports are compared with (tests/test_identifier.py). Run by
 * scripts/python_golden.sh.
 *
 * Usage: c_export STREAM OUTDIR. STREAM: n records of 60 bytes, little-endian: time (µs, u64),
 * then 13 f32: attitude [roll pitch yaw] (rad), velocity [v_x v_y v_z] (m/s, paper axes),
 * rates [q r p] (deg/s), controls [col ped lon lat]. Writes OUTDIR/KIND.bin for each kind: the
 * export after stepping every sample (a refused sample ends the run with status 2). */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "rotorid.h"

static ROTORID_STORAGE(storage, ROTORID_EXTENDED_FUZZY_STORAGE_SIZE);
static uint8_t exported[ROTORID_EXTENDED_FUZZY_EXPORT_SIZE];

static const struct {
    uint32_t kind;
    const char *name;
} KINDS[] = {
    {ROTORID_KIND_FLIGHT, "flight"},
    {ROTORID_KIND_FLIGHT_PLAIN, "flight_plain"},
    {ROTORID_KIND_PAPER_FUZZY, "paper_fuzzy"},
    {ROTORID_KIND_PAPER_PLAIN, "paper_plain"},
    {ROTORID_KIND_EXTENDED_FUZZY, "extended_fuzzy"},
    {ROTORID_KIND_EXTENDED_PLAIN, "extended_plain"},
    {ROTORID_KIND_PAPER_LOCAL, "paper_local"},
    {ROTORID_KIND_EXTENDED_LOCAL, "extended_local"},
};

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: c_export STREAM OUTDIR\n");
        return 1;
    }
    for (size_t k = 0; k < sizeof KINDS / sizeof KINDS[0]; k++) {
        FILE *in = fopen(argv[1], "rb");
        if (!in) return 1;
        rotorid_ident_t *id = NULL;
        rotorid_error_t err;
        if (rotorid_init(storage, sizeof storage, KINDS[k].kind, NULL, NULL, &id, &err) != ROTORID_OK)
            return 1;
        uint8_t rec[60];
        while (fread(rec, 1, sizeof rec, in) == sizeof rec) {
            rotorid_sample_t s;
            memset(&s, 0, sizeof s);
            float f[13];
            memcpy(&s.time_us, rec, 8); /* the host is little-endian (x86-64, AArch64) */
            memcpy(f, rec + 8, sizeof f);
            s.roll = f[0];
            s.pitch = f[1];
            s.yaw = f[2];
            memcpy(s.velocity, f + 3, 3 * sizeof(float));
            memcpy(s.rates, f + 6, 3 * sizeof(float));
            memcpy(s.controls, f + 9, 4 * sizeof(float));
            s.attitude_form = ROTORID_ATTITUDE_EULER;
            rotorid_step_output_t out;
            if (rotorid_step(id, &s, &out, &err) != ROTORID_OK) return 2;
        }
        fclose(in);
        size_t len = 0;
        if (rotorid_export(id, exported, sizeof exported, &len, &err) != ROTORID_OK) return 3;
        char path[4096];
        snprintf(path, sizeof path, "%s/%s.bin", argv[2], KINDS[k].name);
        FILE *out = fopen(path, "wb");
        if (!out || fwrite(exported, 1, len, out) != len) return 4;
        fclose(out);
    }
    return 0;
}
