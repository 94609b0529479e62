/* Quantities with unit suffixes in decks: "5 fs", "0.9 nm", "9 A", "298 K", "1 g/cm3". */
#ifndef ROTLEAP_APP_QUANTITY_H
#define ROTLEAP_APP_QUANTITY_H
#include <rotleap/units.h>
#include <stddef.h>

typedef enum { Q_NONE = 0, Q_LENGTH, Q_TIME, Q_TEMPERATURE, Q_DENSITY, Q_ENERGY, Q_PRESSURE, Q_COMPRESSIBILITY,
               Q_INVLENGTH } rl_dim;

/* Parse `text` as a number with an optional unit suffix of dimension `dim` in unit system `u`,
 * into the system's base unit (real: nm, ps, K, amu/nm^3, kJ/mol, kJ mol^-1 nm^-3 for pressures and its inverse for
 * compressibilities, 1/nm; lj: reduced, where a suffix is
 * an error).  "inf" is accepted when allow_inf.  Returns 0, or -1 with a message in err. */
int rl_parse_quantity(const char *text, rl_dim dim, rl_units u, int allow_inf, double *out,
                      char *err, size_t errlen);
/* The default unit of a dimension in a unit system ("nm", "ps", ... or "reduced"), and the
 * accepted suffixes, for help texts. */
const char *rl_dim_unit(rl_dim dim, rl_units u);
const char *rl_dim_suffixes(rl_dim dim);
#endif
