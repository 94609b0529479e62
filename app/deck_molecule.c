/* Deck molecules: [molecule NAME] sections in a deck or in the file system.molecules names
 * (docs/deck.md, "Molecules"), parsed into rl_deck_molecule and built with rl_molecule_build. */
#include "deck_internal.h"
#include "quantity.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* The molecule a [molecule NAME] section defines: its index, or -1 if section is not one. */
int deck_molecule_section(const raw_deck *r, const char *section)
{
  if (strncmp(section, "molecule", 8) || (section[8] && !isspace((unsigned char)section[8]))) return -1;
  const char *name = section + 8;
  while (isspace((unsigned char)*name)) name++;
  for (int i = r->nmol - 1; i >= 0; i--)
    if (!strcmp(r->mol[i].name, name)) return i;
  return -1;
}

/* A section header [name]: 1 if its keys are to be read.  [molecule NAME] registers a molecule
 * (a name of letters, digits and _ + - . at most 31 characters, defined once, not a catalogue
 * model's); in a molecule file no other section is allowed. */
int deck_new_molecule(raw_deck *r, const char *name)
{
  if (strncmp(name, "molecule", 8) || (name[8] && !isspace((unsigned char)name[8]))) {
    if (r->molfile) { deck_problem(r, r->lineno, "[%s]: a molecule file holds [molecule NAME] sections only", name); return 0; }
    return 1;
  }
  const char *mn = name + 8;
  while (isspace((unsigned char)*mn)) mn++;
  size_t n = strlen(mn), ok = n > 0 && n < sizeof ((rl_deck_molecule *)0)->name;
  for (size_t i = 0; i < n && ok; i++) ok = isalnum((unsigned char)mn[i]) || strchr("_+-.", mn[i]);
  if (!ok) {
    deck_problem(r, r->lineno, "[%s]: a molecule's name is 1 to %zu letters, digits or _ + - . ([molecule water])", name,
            sizeof ((rl_deck_molecule *)0)->name - 1);
    return 0;
  }
  for (int i = 0; i < r->nmol; i++)
    if (!strcmp(r->mol[i].name, mn)) {
      deck_problem(r, r->lineno, "[molecule %s] is defined twice (first at %s:%d)", mn, r->mol[i].file, r->mol[i].line);
      return 0;
    }
  for (int i = 0; i < rl_catalog_count(); i++)
    if (!strcmp(rl_catalog_get(i)->name, mn)) {
      deck_problem(r, r->lineno, "[molecule %s]: the catalogue has a model of that name (rotleap models): give yours another", mn);
      return 0;
    }
  if (r->nmol == RL_DECK_MAX_MOLECULES) {
    deck_problem(r, r->lineno, "[molecule %s]: more than %d molecules defined", mn, RL_DECK_MAX_MOLECULES);
    return 0;
  }
  if (!(r->mol[r->nmol].name = strdup(mn))) { deck_problem(r, r->lineno, "out of memory"); return 0; }
  r->mol[r->nmol].file = r->path;
  r->mol[r->nmol++].line = r->lineno;
  return 1;
}

/* ---- molecules a deck defines ([molecule NAME]) -------------------------------------------- */

static int user_define(const rl_model *self, const double *params, int force_general, rl_molecule *m)
{
  (void)params;
  const rl_deck_molecule *u = (const rl_deck_molecule *)self; /* model is its first member */
  const char *names[RL_MOLECULE_MAX_SITES];
  for (int a = 0; a < u->nsites; a++) names[a] = u->site_names[a];
  const rl_molecule_def def = {u->name, u->nsites, names, &u->pos[0][0], u->mass, u->sigma, u->epsilon, u->charge,
                               &u->dipole[0][0], u->quadrupole, {u->inertia[0], u->inertia[1], u->inertia[2]},
                               u->symmetrize ? RL_DECK_SYMMETRIZE_RTOL : 0.0};
  return rl_molecule_build(&def, force_general, m);
}

const rl_deck_molecule *rl_deck_user_model(const rl_model *m)
{
  return m && m->define == user_define ? (const rl_deck_molecule *)m : NULL;
}

const rl_deck_molecule *rl_deck_user_molecule(const rl_deck *d) { return rl_deck_user_model(d->model); }

/* The units of a site's quantities that are not deck quantities (quantity.c): mass, charge,
 * dipole, quadrupole.  1 D = 0.020819434 e nm (CODATA: 3.33564e-30 C m). */
typedef enum { SQ_LENGTH, SQ_ENERGY, SQ_MASS, SQ_CHARGE, SQ_DIPOLE, SQ_QUADRUPOLE } site_qty;
static const struct { site_qty q; const char *suffix; double factor; } site_units[] = {
    {SQ_MASS, "amu", 1.0},        {SQ_MASS, "u", 1.0},           {SQ_MASS, "g/mol", 1.0},
    {SQ_CHARGE, "e", 1.0},        {SQ_DIPOLE, "e*nm", 1.0},      {SQ_DIPOLE, "D", 0.020819434},
    {SQ_DIPOLE, "e*A", 0.1},      {SQ_QUADRUPOLE, "e*nm^2", 1.0}, {SQ_QUADRUPOLE, "D*A", 0.0020819434},
    {SQ_QUADRUPOLE, "e*A^2", 0.01}};
static const char *const site_keywords[] = {"mass", "charge", "sigma", "epsilon", "dipole", "quadrupole"};

static int site_keyword(const char *t)
{
  for (int k = 0; k < 6; k++)
    if (!strcmp(t, site_keywords[k])) return k;
  return -1;
}

/* 1 if token t starts with a number; the rest (an attached unit) in *rest. */
static int numeric(const char *t, const char **rest)
{
  char *end;
  (void)strtod(t, &end);
  *rest = end;
  return end != t;
}

/* One value of a site: the number `num` (with an attached unit, or `unit` from the token after
 * the numbers, or bare) as quantity q in units u.  0, or -1 with a message in err. */
static int site_value(const char *num, const char *unit, site_qty q, rl_units u, double *out, char *err, size_t n)
{
  const char *att;
  numeric(num, &att);
  const char *un = *att ? att : unit ? unit : "";
  if (q == SQ_LENGTH || q == SQ_ENERGY) {
    char buf[DECK_LINE_MAX + 32]; /* a token of a line: never cut */
    snprintf(buf, sizeof buf, "%.*s%s%s", (int)(att - num), num, *un ? " " : "", un);
    return rl_parse_quantity(buf, q == SQ_LENGTH ? Q_LENGTH : Q_ENERGY, u, 0, out, err, n);
  }
  char *end;
  const double x = strtod(num, &end);
  if (!isfinite(x)) { snprintf(err, n, "'%s' is not a finite number", num); return -1; }
  double f = 1.0;
  if (*un) {
    if (u == RL_UNITS_LJ) { snprintf(err, n, "reduced (lj) units take no unit suffix (got '%s')", un); return -1; }
    int found = 0;
    for (size_t k = 0; k < sizeof site_units / sizeof site_units[0] && !found; k++)
      if (site_units[k].q == q && !strcmp(site_units[k].suffix, un)) { f = site_units[k].factor; found = 1; }
    if (!found) {
      snprintf(err, n, "unit '%s' is not known here (mass: amu; charge: e; dipole: D, e*nm, e*A; quadrupole: D*A, "
               "e*nm^2, e*A^2; bare numbers are in the first)", un);
      return -1;
    }
  }
  *out = x * f;
  return 0;
}

/* A site line: "NAME x y z [UNIT] mass M [charge Q] [sigma S [UNIT]] [epsilon E [UNIT]]
 * [dipole dx dy dz [UNIT]] [quadrupole Q [UNIT]]" into site a of dm.  0, or -1 reported. */
static int site_line(raw_deck *r, const char *file, int line, const char *text, rl_deck_molecule *dm, int a)
{
  char *buf = strdup(text), *save, *tok[64];
  if (!buf) { deck_problem_at(r, file, line, "out of memory"); return -1; }
  int nt = 0, st = 0;
  for (char *t = strtok_r(buf, " \t", &save); t; t = strtok_r(NULL, " \t", &save)) {
    if (nt == 64) { deck_problem_at(r, file, line, "site: too many words"); free(buf); return -1; }
    tok[nt++] = t;
  }
  const char *rest;
  char err[256];
  int given[6] = {0};
#define SITE_FAIL(...) do { deck_problem_at(r, file, line, __VA_ARGS__); st = -1; goto done; } while (0)
  if (nt < 4) SITE_FAIL("site = NAME x y z [unit] mass M ...: give a name and three coordinates (got '%s')", text);
  if (numeric(tok[0], &rest) || strlen(tok[0]) >= sizeof dm->site_names[0] || site_keyword(tok[0]) >= 0)
    SITE_FAIL("site: '%s' is not a site name (1 to %zu characters, not a number or a keyword)", tok[0],
              sizeof dm->site_names[0] - 1);
  for (int b = 0; b < a; b++)
    if (!strcmp(dm->site_names[b], tok[0])) SITE_FAIL("site %s: two sites of one name (RDFs and pair overrides name sites)", tok[0]);
  snprintf(dm->site_names[a], sizeof dm->site_names[a], "%s", tok[0]);
  int i = 1;
  /* groups: the position (3 numbers), then keyword + 1 or 3 numbers, each with an optional unit */
  for (int g = -1; i < nt || g < 0; g++) {
    int kw = -1, nnum = 3;
    if (g >= 0) {
      kw = site_keyword(tok[i]);
      if (kw < 0) SITE_FAIL("site %s: '%s' is not one of mass, charge, sigma, epsilon, dipole, quadrupole", tok[0], tok[i]);
      if (given[kw]) SITE_FAIL("site %s: %s given twice", tok[0], tok[i]);
      given[kw] = 1;
      nnum = kw == 4 ? 3 : 1;
      i++;
    }
    const char *what = kw < 0 ? "position" : site_keywords[kw];
    const int first = i;
    for (int k = 0; k < nnum; k++, i++)
      if (i >= nt || !numeric(tok[i], &rest)) SITE_FAIL("site %s: %s needs %d number%s", tok[0], what, nnum, nnum > 1 ? "s" : "");
    const char *unit = i < nt && site_keyword(tok[i]) < 0 && !numeric(tok[i], &rest) ? tok[i++] : NULL;
    static const site_qty qty[6] = {SQ_MASS, SQ_CHARGE, SQ_LENGTH, SQ_ENERGY, SQ_DIPOLE, SQ_QUADRUPOLE};
    const site_qty q = kw < 0 ? SQ_LENGTH : qty[kw];
    double v[3];
    for (int k = 0; k < nnum; k++)
      if (site_value(tok[first + k], unit, q, dm->model.units, &v[k], err, sizeof err)) SITE_FAIL("site %s: %s: %s", tok[0], what, err);
    if ((kw == 0 || kw == 2 || kw == 3) && !(v[0] >= 0))
      SITE_FAIL("site %s: %s %g must be >= 0", tok[0], what, v[0]);
    switch (kw) {
    case -1: memcpy(dm->pos[a], v, sizeof dm->pos[a]); break;
    case 0: dm->mass[a] = v[0]; break;
    case 1: dm->charge[a] = v[0]; break;
    case 2: dm->sigma[a] = v[0]; break;
    case 3: dm->epsilon[a] = v[0]; break;
    case 4: memcpy(dm->dipole[a], v, sizeof dm->dipole[a]); break;
    default: dm->quadrupole[a] = v[0]; break;
    }
  }
  if (!given[0]) SITE_FAIL("site %s has no mass: write mass M (mass 0 for a massless site, like TIP4P's M)", tok[0]);
  if (given[2] != given[3]) SITE_FAIL("site %s: give sigma and epsilon together (an LJ site needs both)", tok[0]);
#undef SITE_FAIL
done:
  free(buf);
  return st;
}

/* The molecule i's lines into dm, checked; then built (rl_molecule_build), its messages at the
 * line of the site they name.  0, or the number of problems reported. */
static int parse_molecule(raw_deck *r, int i, rl_deck_molecule *dm)
{
  const int before = r->problems;
  const char *file = r->mol[i].file;
  memset(dm, 0, sizeof *dm);
  snprintf(dm->name, sizeof dm->name, "%s", r->mol[i].name);
  dm->model.name = dm->name;
  dm->model.description = "a molecule defined in a deck";
  dm->model.reference = "the deck's [molecule] section";
  dm->model.units = RL_UNITS_REAL;
  dm->model.define = user_define;
  int site_line_no[RL_MOLECULE_MAX_SITES], seen_units = 0, seen[4] = {0};
  /* units first: the sites' values depend on them */
  for (int j = 0; j < r->nml; j++)
    if (r->ml[j].mol == i && !strcmp(r->ml[j].key, "units")) {
      if (seen_units) deck_problem_at(r, r->ml[j].file, r->ml[j].line, "[molecule %s] units given twice", dm->name);
      seen_units = 1;
      if (!strcmp(r->ml[j].val, "lj")) dm->model.units = RL_UNITS_LJ;
      else if (strcmp(r->ml[j].val, "real"))
        deck_problem_at(r, r->ml[j].file, r->ml[j].line, "[molecule %s] units: '%s' is not real or lj", dm->name, r->ml[j].val);
    }
  for (int j = 0; j < r->nml; j++) {
    if (r->ml[j].mol != i) continue;
    const char *k = r->ml[j].key, *v = r->ml[j].val, *f = r->ml[j].file;
    const int ln = r->ml[j].line;
    static const char *const single[4] = {"inertia", "symmetrize", "mixing", "description"};
    for (int s = 0; s < 4; s++)
      if (!strcmp(k, single[s]) && seen[s]++) deck_problem_at(r, f, ln, "[molecule %s] %s given twice", dm->name, k);
    if (!strcmp(k, "units")) continue;
    if (!strcmp(k, "site")) {
      if (dm->nsites == RL_MOLECULE_MAX_SITES) {
        deck_problem_at(r, f, ln, "[molecule %s]: more than %d sites", dm->name, RL_MOLECULE_MAX_SITES);
        continue;
      }
      if (!site_line(r, f, ln, v, dm, dm->nsites)) site_line_no[dm->nsites++] = ln;
    } else if (!strcmp(k, "inertia")) { /* a single-centre dipole's moment I (or I I I) */
      char *end;
      double x[3];
      int n = 0;
      const char *p = v;
      while (n < 3 && *p) {
        x[n] = strtod(p, &end);
        if (end == p) break;
        n++;
        p = end + strspn(end, " \t");
      }
      if (*p || (n != 1 && n != 3) || !isfinite(x[0]) || !(x[0] > 0) || (n == 3 && (!isfinite(x[1]) || !isfinite(x[2]))))
        deck_problem_at(r, f, ln, "[molecule %s] inertia: '%s' is not one positive number or three (%s)", dm->name, v,
                   dm->model.units == RL_UNITS_LJ ? "m sigma^2" : "amu nm^2");
      else for (int c = 0; c < 3; c++) dm->inertia[c] = x[n == 1 ? 0 : c];
    } else if (!strcmp(k, "symmetrize")) {
      if (!strcmp(v, "yes")) dm->symmetrize = 1;
      else if (strcmp(v, "no")) deck_problem_at(r, f, ln, "[molecule %s] symmetrize: '%s' is not yes or no", dm->name, v);
    } else if (!strcmp(k, "mixing")) {
      if (!strcmp(v, "geometric")) dm->model.geometric_mixing = 1;
      else if (strcmp(v, "lorentz-berthelot"))
        deck_problem_at(r, f, ln, "[molecule %s] mixing: '%s' is not lorentz-berthelot or geometric", dm->name, v);
    } else if (strcmp(k, "description"))
      deck_problem_at(r, f, ln, "[molecule %s]: unknown key '%s' (site, units, inertia, symmetrize, mixing, description)", dm->name, k);
  }
  if (r->problems > before) return r->problems - before;
  if (!dm->nsites) {
    deck_problem_at(r, file, r->mol[i].line, "[molecule %s] has no sites (site = NAME x y z mass M ...)", dm->name);
    return r->problems - before;
  }
  /* coincident sites: one site carries all of a point's parameters */
  double ext = 0.0;
  for (int a = 0; a < dm->nsites; a++)
    for (int b = 0; b < a; b++)
      ext = fmax(ext, hypot(hypot(dm->pos[a][0] - dm->pos[b][0], dm->pos[a][1] - dm->pos[b][1]), dm->pos[a][2] - dm->pos[b][2]));
  for (int a = 0; a < dm->nsites; a++)
    for (int b = 0; b < a; b++) {
      const double dist = hypot(hypot(dm->pos[a][0] - dm->pos[b][0], dm->pos[a][1] - dm->pos[b][1]), dm->pos[a][2] - dm->pos[b][2]);
      if (dist <= 1e-9 * ext || dist == 0.0) {
        deck_problem_at(r, file, site_line_no[a], "[molecule %s] sites %s and %s coincide: give one site all of the "
                   "point's parameters", dm->name, dm->site_names[b], dm->site_names[a]);
        return r->problems - before;
      }
    }
  rl_molecule m;
  if (rl_model_build(&dm->model, NULL, 0, &m)) {
    const char *msg = rl_last_error(), *at = strstr(msg, ": site ");
    int a = -1;
    if (at && sscanf(at, ": site %d (", &a) != 1) a = -1;
    const int ln = a >= 0 && a < dm->nsites ? site_line_no[a] : r->mol[i].line;
    deck_problem_at(r, file, ln, "[molecule %s]: %s", dm->name, msg);
    return r->problems - before;
  }
  dm->model.family = m.natural_kind;
  return 0;
}

/* system.molecules: the file's [molecule] sections, read like the deck's (the same line format),
 * a relative path taken from the deck's directory. */
static void read_molecule_file(raw_deck *r, const char *deck)
{
  const char *v = r->val[K_MOLFILE];
  struct stat sd;
  const int from_dir = v[0] != '/' && !stat(deck, &sd) && S_ISREG(sd.st_mode) && strrchr(deck, '/');
  const size_t dn = from_dir ? (size_t)(strrchr(deck, '/') - deck) + 1 : 0;
  if (!(r->molpath = malloc(dn + strlen(v) + 1))) { deck_problem(r, r->line[K_MOLFILE], "out of memory"); return; }
  memcpy(r->molpath, deck, dn);
  strcpy(r->molpath + dn, v);
  struct stat sb;
  FILE *f = NULL;
  if (stat(r->molpath, &sb)) deck_problem(r, r->line[K_MOLFILE], "system.molecules: cannot open %s: %s", r->molpath, strerror(errno));
  else if (!S_ISREG(sb.st_mode)) deck_problem(r, r->line[K_MOLFILE], "system.molecules: %s is not a regular file (%s)", r->molpath, deck_file_kind(sb.st_mode));
  else if (sb.st_size > DECK_BYTES_MAX) deck_problem(r, r->line[K_MOLFILE], "system.molecules: %s is more than 1 MiB", r->molpath);
  else if (!(f = fopen(r->molpath, "r"))) deck_problem(r, r->line[K_MOLFILE], "system.molecules: cannot open %s: %s", r->molpath, strerror(errno));
  if (!f) return;
  const char *deck_path = r->path;
  char *section = r->section;
  const int lineno = r->lineno, bad = r->section_bad;
  const long bytes = r->bytes;
  r->path = r->molpath;
  r->section = NULL;
  r->lineno = 0;
  r->section_bad = 0;
  r->bytes = 0;
  r->molfile = 1;
  deck_read(f, r);
  fclose(f);
  free(r->section);
  r->molfile = 0;
  r->path = deck_path;
  r->section = section;
  r->lineno = lineno;
  r->section_bad = bad;
  r->bytes = bytes;
  r->stopped = 0;
}

/* A model by name: the deck's molecules first, then the catalogue.  NULL, reported at key k,
 * unless the molecule is defined with problems reported already. */
static const rl_model *find_model(raw_deck *r, rl_deck *d, const char *name, int k, const char *what, int before)
{
  for (int i = 0; i < d->nmolecules; i++)
    if (!strcmp(d->molecules[i].name, name)) return &d->molecules[i].model;
  for (int i = 0; i < r->nmol; i++)
    if (!strcmp(r->mol[i].name, name)) return NULL; /* defined, with its problems reported */
  if (r->val[K_MOLFILE] && before < r->problems) return NULL; /* perhaps defined in a file that did not load */
  const rl_model *m = rl_catalog_find(name);
  if (!m) deck_problem(r, r->line[k], "%s: %s%s", what, rl_last_error(), r->nmol ? " (or a [molecule NAME] of the deck)" : "");
  return m;
}

/* system.species = NAME:COUNT ...: d->species, d->model (the first's) and d->count (the sum). */
static void resolve_species(raw_deck *r, rl_deck *d, int before)
{
  const int line = r->line[K_SPECIES];
  for (int k = K_MODEL; k <= K_COUNT; k += K_COUNT - K_MODEL)
    if (r->val[k]) deck_problem(r, r->line[k], "system.%s: give system.species or system.model and system.count, not both",
                                k == K_MODEL ? "model" : "count");
  if (r->nmodel) deck_problem(r, r->model_line[0], "[model] parameters are for system.model; the species of system.species "
                              "take their models' defaults (define a [molecule NAME] for other values)");
  if (r->bad[K_SPECIES]) return;
  char *buf = strdup(r->val[K_SPECIES]), *save;
  if (!buf) { deck_problem(r, line, "out of memory"); return; }
  long total = 0;
  int ok = 1;
  for (char *t = strtok_r(buf, " \t", &save); t; t = strtok_r(NULL, " \t", &save)) {
    char *colon = strrchr(t, ':'), *end;
    if (!colon || colon == t) {
      deck_problem(r, line, "system.species: '%s' is not NAME:COUNT (spce:500 na:10 cl:10)", t);
      ok = 0;
      continue;
    }
    *colon = '\0';
    errno = 0;
    const long n = strtol(colon + 1, &end, 10);
    if (end == colon + 1 || *end || errno || n < 1 || n > INT_MAX) {
      deck_problem(r, line, "system.species: %s:%s: the count must be a whole number >= 1%s", t, colon + 1,
                   end != colon + 1 && !*end && n == 0 ? " (leave out a species with no molecules)" : "");
      ok = 0;
      continue;
    }
    for (int k = 0; k < d->nspecies; k++)
      if (!strcmp(d->species[k].model->name, t)) {
        deck_problem(r, line, "system.species: %s is named twice (give one count)", t);
        ok = 0;
      }
    if (d->nspecies == RL_DECK_MAX_SPECIES) {
      deck_problem(r, line, "system.species: more than %d species", RL_DECK_MAX_SPECIES);
      ok = 0;
      break;
    }
    const rl_model *m = find_model(r, d, t, K_SPECIES, "system.species", before);
    if (!m) { ok = 0; continue; }
    if (d->nspecies && m->units != d->species[0].model->units) {
      deck_problem(r, line, "system.species: %s is in %s units, %s in %s: a mixture's species share one unit system", t,
                   m->units == RL_UNITS_LJ ? "reduced (lj)" : "real", d->species[0].model->name,
                   d->species[0].model->units == RL_UNITS_LJ ? "reduced (lj)" : "real");
      ok = 0;
      continue;
    }
    d->species[d->nspecies].model = m;
    d->species[d->nspecies++].count = (int)n;
    total += n;
  }
  free(buf);
  if (ok && !d->nspecies) deck_problem(r, line, "system.species: no species (spce:500 na:10 cl:10)");
  else if (ok && total > INT_MAX) deck_problem(r, line, "system.species: %ld molecules in all, more than %d", total, INT_MAX);
  if (!ok || !d->nspecies || total > INT_MAX) { d->nspecies = 0; return; }
  d->model = d->species[0].model;
  d->count = (int)total;
}

/* A reference SPECIES:SITE of interactions.pairs: 0 with the indices, or -1 reported. */
static int site_ref(raw_deck *r, const rl_deck *d, const char *t, int *species, int *site)
{
  const int line = r->line[K_PAIRS];
  const char *colon = strrchr(t, ':');
  if (!colon || colon == t || !colon[1]) {
    deck_problem(r, line, "interactions.pairs: '%s' is not SPECIES:SITE (na:Na)", t);
    return -1;
  }
  const int n = (int)(colon - t);
  for (int k = 0; k < d->nspecies; k++) {
    if (strncmp(d->species[k].model->name, t, (size_t)n) || d->species[k].model->name[n]) continue;
    rl_molecule m;
    if (rl_model_build(d->species[k].model, k ? NULL : d->params, 0, &m)) return -1; /* reported with the model */
    char have[RL_MOLECULE_MAX_SITES * 10] = "";
    for (int a = 0; a < m.nsites; a++) {
      if (!strcmp(m.site_names[a], colon + 1)) { *species = k; *site = a; return 0; }
      snprintf(have + strlen(have), sizeof have - strlen(have), "%s%s", a ? ", " : "", m.site_names[a]);
    }
    deck_problem(r, line, "interactions.pairs: species %.*s has no site '%s' (its sites: %s)", n, t, colon + 1, have);
    return -1;
  }
  char have[RL_DECK_MAX_SPECIES * 40] = "";
  for (int k = 0; k < d->nspecies; k++)
    snprintf(have + strlen(have), sizeof have - strlen(have), "%s%s", k ? ", " : "", d->species[k].model->name);
  deck_problem(r, line, "interactions.pairs: '%.*s' is not a species of the deck (%s)", n, t, have);
  return -1;
}

void deck_pairs(raw_deck *r, rl_deck *d)
{
  const int line = r->line[K_PAIRS];
  char *buf = strdup(r->val[K_PAIRS]), *save, *tsave;
  if (!buf) { deck_problem(r, line, "out of memory"); return; }
  for (char *e = strtok_r(buf, ",", &save); e; e = strtok_r(NULL, ",", &save)) {
    char *tok[8];
    int nt = 0;
    for (char *t = strtok_r(e, " \t", &tsave); t; t = strtok_r(NULL, " \t", &tsave)) {
      if (nt == 8) { nt = 9; break; }
      tok[nt++] = t;
    }
    if (nt < 6 || nt > 8) {
      deck_problem(r, line, "interactions.pairs: each pair is SPECIES:SITE SPECIES:SITE sigma S [unit] epsilon E [unit]");
      continue;
    }
    rl_deck_pair p;
    if (site_ref(r, d, tok[0], &p.species[0], &p.site[0]) | site_ref(r, d, tok[1], &p.species[1], &p.site[1])) continue;
    int i = 2, bad = 0;
    double v[2] = {-1, -1};
    for (int q = 0; q < 2 && !bad; q++) {
      const char *kw = q ? "epsilon" : "sigma";
      const char *rest;
      if (i + 1 >= nt || strcmp(tok[i], kw) || !numeric(tok[i + 1], &rest)) {
        deck_problem(r, line, "interactions.pairs: %s %s: expected '%s' and a number", tok[0], tok[1], kw);
        bad = 1;
        break;
      }
      const char *unit = i + 2 < nt && strcmp(tok[i + 2], "epsilon") && !numeric(tok[i + 2], &rest) ? tok[i + 2] : NULL;
      char err[256];
      const int st = site_value(tok[i + 1], unit, q ? SQ_ENERGY : SQ_LENGTH, d->units, &v[q], err, sizeof err);
      if (st || !(v[q] >= 0)) {
        deck_problem(r, line, "interactions.pairs: %s %s: %s: %s", tok[0], tok[1], kw, st ? err : "must be >= 0");
        bad = 1;
      }
      i += unit ? 3 : 2;
    }
    if (bad) continue;
    if (i != nt) { deck_problem(r, line, "interactions.pairs: %s %s: '%s' is left over", tok[0], tok[1], tok[i]); continue; }
    if (d->npairs == RL_DECK_MAX_PAIRS) { deck_problem(r, line, "interactions.pairs: more than %d pairs", RL_DECK_MAX_PAIRS); break; }
    p.sigma = v[0];
    p.epsilon = v[1];
    d->pairs[d->npairs++] = p;
  }
  free(buf);
}

/* system.residues = RES:SPECIES ...: d->residues (species by their system.species names). */
void deck_residues(raw_deck *r, rl_deck *d)
{
  const int line = r->line[K_RESIDUES];
  const size_t len = strlen(d->start);
  if (len < 4 || strcmp(d->start + len - 4, ".pdb")) {
    deck_problem(r, line, "system.residues: names the residues of a .pdb start, and system.start is %s",
                 d->start[0] ? d->start : "lattice");
    return;
  }
  char *buf = strdup(r->val[K_RESIDUES]), *save;
  if (!buf) { deck_problem(r, line, "out of memory"); return; }
  for (char *t = strtok_r(buf, " \t", &save); t; t = strtok_r(NULL, " \t", &save)) {
    char *colon = strchr(t, ':');
    if (!colon || colon == t || !colon[1]) {
      deck_problem(r, line, "system.residues: '%s' is not RES:SPECIES (SOL:tip4p-ew)", t);
      continue;
    }
    *colon = '\0';
    if (strlen(t) > 4) {
      deck_problem(r, line, "system.residues: residue name '%s' has more than 4 characters (PDB columns 18-21)", t);
      continue;
    }
    int k = 0;
    while (k < d->nspecies && strcmp(d->species[k].model->name, colon + 1)) k++;
    if (k == d->nspecies) {
      char have[RL_DECK_MAX_SPECIES * 40] = "";
      for (int q = 0; q < d->nspecies; q++)
        snprintf(have + strlen(have), sizeof have - strlen(have), "%s%s", q ? ", " : "", d->species[q].model->name);
      deck_problem(r, line, "system.residues: %s:%s: '%s' is not a species of the deck (%s)", t, colon + 1, colon + 1, have);
      continue;
    }
    int twice = 0;
    for (int j = 0; j < d->nresidues; j++) twice |= !strcasecmp(d->residues[j].name, t);
    if (twice) { deck_problem(r, line, "system.residues: residue name %s is given twice", t); continue; }
    if (d->nresidues == RL_DECK_MAX_RESIDUES) {
      deck_problem(r, line, "system.residues: more than %d residue names", RL_DECK_MAX_RESIDUES);
      break;
    }
    snprintf(d->residues[d->nresidues].name, sizeof d->residues[0].name, "%s", t);
    d->residues[d->nresidues++].species = k;
  }
  free(buf);
}

/* Every [molecule] section parsed into d->molecules; system.model resolved among them first,
 * then in the catalogue. */
void deck_resolve_model(raw_deck *r, rl_deck *d)
{
  const int before = r->problems;
  if (r->val[K_MOLFILE] && !r->bad[K_MOLFILE]) read_molecule_file(r, d->path);
  for (int i = 0; i < r->nmol; i++)
    if (!parse_molecule(r, i, &d->molecules[d->nmolecules])) d->nmolecules++;
  if (r->val[K_SPECIES]) { resolve_species(r, d, before); return; }
  deck_require(r, K_MODEL);
  if (!r->val[K_MODEL] || r->bad[K_MODEL]) return;
  for (int i = 0; i < d->nmolecules; i++)
    if (!strcmp(d->molecules[i].name, r->val[K_MODEL])) { d->model = &d->molecules[i].model; return; }
  for (int i = 0; i < r->nmol; i++)
    if (!strcmp(r->mol[i].name, r->val[K_MODEL])) return; /* defined, with its problems reported */
  if (r->val[K_MOLFILE] && before < r->problems) return;   /* perhaps defined in a file that did not load */
  d->model = rl_catalog_find(r->val[K_MODEL]);
  if (!d->model)
    deck_problem(r, r->line[K_MODEL], "system.model: %s%s", rl_last_error(), r->nmol ? " (or a [molecule NAME] of the deck)" : "");
}
