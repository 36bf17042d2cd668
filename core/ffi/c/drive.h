/* The C driver shared by the host test and the Cortex-M4F firmware (see drive.c). */
#ifndef DRIVE_H
#define DRIVE_H

#include "rotorid.h"

/* Which kinds run, and the storage and export buffer sized for the largest of them. The host
 * runs all eight; the firmware (64 KiB RAM) leaves out EXTENDED_FUZZY, whose 27 KiB of state
 * (and as much stack to build it) do not fit beside the rest. */
#if defined(DRIVE_ONLY) /* one kind, to measure its stack and flash (DRIVE_ONLY_INIT: its rotorid_init_<kind>) */
#define DRIVE_KINDS DRIVE_ONLY
#if DRIVE_ONLY == 5
#define DRIVE_STORAGE_SIZE ROTORID_EXTENDED_FUZZY_STORAGE_SIZE
#define DRIVE_EXPORT_SIZE ROTORID_EXTENDED_FUZZY_EXPORT_SIZE
#else
#define DRIVE_STORAGE_SIZE ROTORID_PAPER_FUZZY_STORAGE_SIZE
#define DRIVE_EXPORT_SIZE ROTORID_PAPER_FUZZY_EXPORT_SIZE
#endif
#elif defined(DRIVE_SMALL)
#define DRIVE_KINDS                                                                       \
    ROTORID_KIND_FLIGHT, ROTORID_KIND_FLIGHT_PLAIN, ROTORID_KIND_PAPER_FUZZY,             \
        ROTORID_KIND_PAPER_PLAIN, ROTORID_KIND_EXTENDED_PLAIN, ROTORID_KIND_PAPER_LOCAL, \
        ROTORID_KIND_EXTENDED_LOCAL
#define DRIVE_STORAGE_SIZE ROTORID_PAPER_FUZZY_STORAGE_SIZE
#define DRIVE_EXPORT_SIZE ROTORID_PAPER_FUZZY_EXPORT_SIZE
#else
#define DRIVE_KINDS                                                                       \
    ROTORID_KIND_FLIGHT, ROTORID_KIND_FLIGHT_PLAIN, ROTORID_KIND_PAPER_FUZZY,             \
        ROTORID_KIND_PAPER_PLAIN, ROTORID_KIND_EXTENDED_FUZZY,                            \
        ROTORID_KIND_EXTENDED_PLAIN, ROTORID_KIND_PAPER_LOCAL, ROTORID_KIND_EXTENDED_LOCAL
#define DRIVE_STORAGE_SIZE ROTORID_EXTENDED_FUZZY_STORAGE_SIZE
#define DRIVE_EXPORT_SIZE ROTORID_EXTENDED_FUZZY_EXPORT_SIZE
#endif

/* Where the driver's report lines go (NUL-terminated, each ending in a newline). */
typedef void (*drive_emit_t)(const char *line);

/* Runs everything; 0 when every check passed, 1 after a FAIL line. */
int drive(drive_emit_t emit);

#endif
