/* Unit suffixes for deck values.  Conversion factors: 1 A = 0.1 nm; 1 fs = 1e-3 ps;
 * 1 g/cm^3 = 602.214076 amu/nm^3 (N_A 1e-21); 1 kcal = 4.184 kJ; energies given in K mean k_B T;
 * 1 /A = 10 /nm (an inverse length: the Ewald splitting parameter). */
#include "quantity.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  rl_dim dim;
  const char *suffix;
  double factor;
} unit_def;

/* The first entry of each dimension is its default unit, rl_dim_unit's (tests/cli checks a
 * bare density against "g/cm3"). */
static const unit_def units[] = {
    {Q_LENGTH, "nm", 1.0},        {Q_LENGTH, "A", 0.1},          {Q_LENGTH, "Å", 0.1},
    {Q_LENGTH, "angstrom", 0.1},  {Q_LENGTH, "pm", 1e-3},        {Q_TIME, "ps", 1.0},
    {Q_TIME, "fs", 1e-3},         {Q_TIME, "ns", 1e3},           {Q_TEMPERATURE, "K", 1.0},
    {Q_DENSITY, "g/cm3", 602.214076}, {Q_DENSITY, "g/cm^3", 602.214076}, {Q_DENSITY, "kg/m3", 0.602214076},
    {Q_ENERGY, "kJ/mol", 1.0},    {Q_ENERGY, "kcal/mol", 4.184}, {Q_ENERGY, "K", RL_KB_KJMOL},
    /* 1 bar = 1e5 J/m^3 = 0.0602214076 kJ mol^-1 nm^-3 */
    {Q_PRESSURE, "bar", 0.0602214076}, {Q_PRESSURE, "atm", 0.0602214076 * 1.01325}, {Q_PRESSURE, "Pa", 0.0602214076e-5},
    {Q_PRESSURE, "MPa", 0.602214076},  {Q_COMPRESSIBILITY, "1/bar", 1.0 / 0.0602214076},
    {Q_COMPRESSIBILITY, "bar^-1", 1.0 / 0.0602214076}, {Q_COMPRESSIBILITY, "1/Pa", 1e5 / 0.0602214076},
    {Q_COMPRESSIBILITY, "Pa^-1", 1e5 / 0.0602214076},
    {Q_INVLENGTH, "/nm", 1.0},    {Q_INVLENGTH, "nm^-1", 1.0},   {Q_INVLENGTH, "1/nm", 1.0},
    {Q_INVLENGTH, "/A", 10.0},    {Q_INVLENGTH, "A^-1", 10.0},   {Q_INVLENGTH, "1/A", 10.0},
    {Q_INVLENGTH, "/Å", 10.0},
};

const char *rl_dim_unit(rl_dim dim, rl_units u)
{
  if (u == RL_UNITS_LJ) return dim == Q_NONE ? "" : "reduced";
  switch (dim) {
  case Q_LENGTH: return "nm";
  case Q_TIME: return "ps";
  case Q_TEMPERATURE: return "K";
  case Q_DENSITY: return "g/cm3";
  case Q_ENERGY: return "kJ/mol";
  case Q_PRESSURE: return "bar";
  case Q_COMPRESSIBILITY: return "1/bar";
  case Q_INVLENGTH: return "/nm";
  default: return "";
  }
}

const char *rl_dim_suffixes(rl_dim dim)
{
  switch (dim) {
  case Q_LENGTH: return "nm, A, pm";
  case Q_TIME: return "fs, ps, ns";
  case Q_TEMPERATURE: return "K";
  case Q_DENSITY: return "g/cm3, kg/m3";
  case Q_ENERGY: return "kJ/mol, kcal/mol, K";
  case Q_PRESSURE: return "bar, atm, Pa, MPa";
  case Q_COMPRESSIBILITY: return "1/bar, bar^-1, 1/Pa, Pa^-1";
  case Q_INVLENGTH: return "/nm, nm^-1, /A, A^-1";
  default: return "";
  }
}

int rl_parse_quantity(const char *text, rl_dim dim, rl_units u, int allow_inf, double *out,
                      char *err, size_t errlen)
{
  while (isspace((unsigned char)*text)) text++;
  if (!*text) { snprintf(err, errlen, "empty value"); return -1; }
  char *end;
  errno = 0;
  double x = strtod(text, &end);
  if (end == text) { snprintf(err, errlen, "'%s' is not a number", text); return -1; }
  if (errno == ERANGE) { snprintf(err, errlen, "'%s' is out of range", text); return -1; }
  if (isnan(x) || (isinf(x) && !allow_inf)) {
    snprintf(err, errlen, "'%s' is not a finite number", text);
    return -1;
  }
  while (isspace((unsigned char)*end)) end++;
  char suffix[32];
  size_t n = strlen(end);
  while (n > 0 && isspace((unsigned char)end[n - 1])) n--;
  if (n >= sizeof suffix) { snprintf(err, errlen, "unit '%s' is not known", end); return -1; }
  memcpy(suffix, end, n);
  suffix[n] = '\0';
  double factor = 1.0;
  if (n == 0 && u != RL_UNITS_LJ) /* a bare number is in the default unit (g/cm3: 602 amu/nm3) */
    for (size_t k = 0; k < sizeof units / sizeof units[0]; k++)
      if (units[k].dim == dim) { factor = units[k].factor; break; }
  if (n > 0) {
    if (dim == Q_NONE) { snprintf(err, errlen, "'%s' takes no unit (got '%s')", text, suffix); return -1; }
    if (u == RL_UNITS_LJ) {
      snprintf(err, errlen, "reduced (lj) units take no unit suffix (got '%s')", suffix);
      return -1;
    }
    int found = 0;
    for (size_t k = 0; k < sizeof units / sizeof units[0]; k++)
      if (units[k].dim == dim && !strcmp(units[k].suffix, suffix)) { factor = units[k].factor; found = 1; break; }
    if (!found) {
      snprintf(err, errlen, "unit '%s' is not %s unit (use %s)", suffix,
               dim == Q_LENGTH ? "a length" : dim == Q_TIME ? "a time" : dim == Q_TEMPERATURE ? "a temperature"
               : dim == Q_DENSITY ? "a density" : dim == Q_INVLENGTH ? "an inverse length"
               : dim == Q_PRESSURE ? "a pressure" : dim == Q_COMPRESSIBILITY ? "a compressibility" : "an energy",
               rl_dim_suffixes(dim));
      return -1;
    }
  }
  if ((x != 0 && x * factor == 0) || (isfinite(x) && !isfinite(x * factor))) { /* 1e308 g/cm3 */
    snprintf(err, errlen, "'%s' is out of range", text);
    return -1;
  }
  *out = x * factor;
  return 0;
}
