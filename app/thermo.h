/* The rows of PREFIX.thermo.csv (docs/files.md), formatted in one place for `rotleap run` and the
 * Python binding's ThermoReporter (python/rotleap/native.c), so that the same deck gives the same
 * bytes from both: the common columns, each force term's energy components, and the optional
 * columns of the deck (under a barostat the volume, density, box edges and pressure tensor; in a
 * mixture each species' temperatures). */
#ifndef ROTLEAP_APP_THERMO_H
#define ROTLEAP_APP_THERMO_H

#include "runrec.h"
#include "scene.h"

#include <stdio.h>

/* The header line (with its newline) of the thermo file of deck d run on scene s (whose terms
 * give the energy columns).  malloc'd; NULL on out of memory. */
char *thermo_header(const rl_deck *d, const scene *s);

/* Appends to f the row (thermo_header's columns) of the STEP report r (r->info set) of deck d on
 * scene s; calE is E's running relative standard deviation of the conserved quantity.  RL_OK, or
 * a status with a message naming `path` (the file f writes) when a write fails. */
int thermo_row(FILE *f, const char *path, const rl_deck *d, const scene *s, const rl_run_report *r, const running *E);

#endif
