/* rotleap: the command-line program.  The library never prints; this file owns all output. */
#include "deck.h"
#include "run.h"
#include "scan.h"

#include <rotleap/catalog.h>
#include <rotleap/rotleap.h>
#include <stdlib.h>

#include <stdio.h>
#include <string.h>

static void usage(FILE *f)
{
  fprintf(f,
          "usage: rotleap COMMAND [options]\n"
          "\n"
          "Molecular dynamics of rigid molecules with Omelyan's revised angular-momentum leapfrog.\n"
          "\n"
          "commands:\n"
          "  run DECK [--set section.key=value ...]\n"
          "              run a simulation described by an INI deck (keys: rotleap run --help)\n"
          "  energy DECK [--json] [--set ...]\n"
          "              evaluate the deck's starting configuration once: energy by term, virial,\n"
          "              pressure, per-molecule force and torque\n"
          "  scan DECK [--timesteps LIST] [--integrators LIST] [--steps N | --time T] ...\n"
          "              the speed-accuracy trade: the deck's scene from one shared start over time\n"
          "              steps and integrators (calE, drift, rigidity, structure, equipartition, cost)\n"
          "  models      list the catalogue of named models: family and rotation path, degrees of\n"
          "              freedom, sites, parameters, units and literature reference\n"
          "  deck-keys [--markdown]\n"
          "              print every deck key with its unit and default (docs/deck.md)\n"
          "\n"
          "options:\n"
          "  -h, --help     this help; `rotleap COMMAND --help` for a command\n"
          "  --version      print the version\n");
}

static int cmd_models(int argc, char **argv)
{
  for (int i = 0; i < argc; i++) {
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      printf("usage: rotleap models\n\nLists every catalogue model with its family, the rotation "
             "path that integrates it,\nits degrees of freedom (translational + rotational), its "
             "sites, adjustable\nparameters with defaults and units, and the literature "
             "reference.\n");
      return 0;
    }
    fprintf(stderr, "rotleap models: unexpected argument '%s'\n", argv[i]);
    return 2;
  }
  printf("%-11s %-5s %-11s %-4s %s\n", "model", "units", "family", "dof", "rotation path");
  for (int i = 0; i < rl_catalog_count(); i++) {
    const rl_model *md = rl_catalog_get(i);
    rl_molecule m;
    if (rl_model_build(md, NULL, 0, &m)) {
      fprintf(stderr, "rotleap models: %s: %s\n", md->name, rl_last_error());
      return 1;
    }
    printf("%-11s %-5s %-11s 3+%d  %s\n", md->name, md->units == RL_UNITS_LJ ? "lj" : "real",
           rl_kind_name(m.kind), rl_kind_rotational_dof(m.kind), rl_kind_rotation_path(m.kind));
    printf("            %s\n            sites:", md->description);
    for (int a = 0; a < m.nsites; a++) printf(" %s", m.site_names[a]);
    printf("  (mass %.4f, moments %.6g %.6g %.6g %s)\n", m.mass, m.inertia[0], m.inertia[1],
           m.inertia[2], md->units == RL_UNITS_LJ ? "m sigma^2" : "amu nm^2");
    if (md->nparams) {
      printf("            parameters:");
      for (int k = 0; k < md->nparams; k++)
        printf(" %s = %g [%s]%s", md->param_names[k], md->param_defaults[k], md->param_units[k],
               k + 1 < md->nparams ? "," : "");
      printf("\n");
    }
    printf("            reference: %s\n", md->reference);
  }
  return 0;
}

/* Common to run and energy: DECK, --set k=v (repeatable), --json (energy only). */
static int deck_command(const char *name, int argc, char **argv, int allow_json)
{
  const char *path = NULL;
  char **sets = calloc((size_t)argc + 1, sizeof *sets);
  int nsets = 0, json = 0;
  for (int i = 0; i < argc; i++) {
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      printf("usage: rotleap %s DECK [--set section.key=value ...]%s\n\n", name, allow_json ? " [--json]" : "");
      if (allow_json)
        printf("Evaluates the starting configuration of DECK once and prints the energy by term, the\n"
               "virial and pressure, and the force and torque on every molecule (CSV, or one JSON\n"
               "object with --json), in the deck's units.  The pressure's kinetic part uses the\n"
               "start's velocities; from a checkpoint (half a step behind), completed to on-step\n"
               "with run.timestep, as the run's thermo row for that state.  A term, virial element,\n"
               "pressure, force or torque that is not finite is an error naming it (exit 1).\n");
      else
        printf("Runs the simulation described by DECK.  Writes PREFIX.thermo.csv (a row every\n"
               "output.thermo_every steps) and PREFIX.summary.txt; problems in the deck are all\n"
               "reported, with file and line, before anything runs.\n");
      printf("\nDeck keys:\n");
      rl_deck_print_keys(stdout, 0);
      free(sets);
      return 0;
    }
    if (!strcmp(argv[i], "--set")) {
      if (i + 1 >= argc) { fprintf(stderr, "rotleap %s: --set needs section.key=value\n", name); free(sets); return 2; }
      sets[nsets++] = argv[++i];
    } else if (!strncmp(argv[i], "--set=", 6)) sets[nsets++] = argv[i] + 6;
    else if (allow_json && !strcmp(argv[i], "--json")) json = 1;
    else if (argv[i][0] == '-') { fprintf(stderr, "rotleap %s: unknown option '%s'\n", name, argv[i]); free(sets); return 2; }
    else if (path) { fprintf(stderr, "rotleap %s: more than one deck ('%s', '%s')\n", name, path, argv[i]); free(sets); return 2; }
    else path = argv[i];
  }
  if (!path) { fprintf(stderr, "rotleap %s: no deck given (rotleap %s --help)\n", name, name); free(sets); return 2; }
  rl_deck d;
  int problems = rl_deck_load(path, sets, nsets, &d, stderr);
  free(sets);
  if (problems) {
    fprintf(stderr, "rotleap %s: %d problem%s in %s; nothing was run\n", name, problems, problems > 1 ? "s" : "", path);
    return 2;
  }
  return allow_json ? rl_app_energy(&d, json) : rl_app_run(&d);
}

int main(int argc, char **argv)
{
  if (argc < 2) { usage(stderr); return 2; }
  const char *cmd = argv[1];
  if (!strcmp(cmd, "-h") || !strcmp(cmd, "--help") || !strcmp(cmd, "help")) { usage(stdout); return 0; }
  if (!strcmp(cmd, "--version")) { printf("rotleap %s\n", ROTLEAP_VERSION); return 0; }
  if (!strcmp(cmd, "models")) return cmd_models(argc - 2, argv + 2);
  if (!strcmp(cmd, "run")) return deck_command("run", argc - 2, argv + 2, 0);
  if (!strcmp(cmd, "scan")) return rl_app_scan(argc - 2, argv + 2);
  if (!strcmp(cmd, "energy")) return deck_command("energy", argc - 2, argv + 2, 1);
  if (!strcmp(cmd, "deck-keys")) {
    rl_deck_print_keys(stdout, argc > 2 && !strcmp(argv[2], "--markdown"));
    return 0;
  }
  fprintf(stderr, "rotleap: unknown command '%s' (try rotleap --help)\n", cmd);
  return 2;
}
