/* The C interface on the host: runs the driver and prints its report to stdout. */
#include <stdio.h>

#include "drive.h"

static void emit(const char *line) { fputs(line, stdout); }

int main(void) { return drive(emit); }
