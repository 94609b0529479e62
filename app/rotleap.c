/* rotleap: the command-line program.  The library never prints; this file owns all output. */
#include <rotleap/catalog.h>
#include <rotleap/rotleap.h>

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
          "  models      list the catalogue of named models: family and rotation path, degrees of\n"
          "              freedom, sites, parameters, units and literature reference\n"
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

int main(int argc, char **argv)
{
  if (argc < 2) { usage(stderr); return 2; }
  const char *cmd = argv[1];
  if (!strcmp(cmd, "-h") || !strcmp(cmd, "--help") || !strcmp(cmd, "help")) { usage(stdout); return 0; }
  if (!strcmp(cmd, "--version")) { printf("rotleap %s\n", ROTLEAP_VERSION); return 0; }
  if (!strcmp(cmd, "models")) return cmd_models(argc - 2, argv + 2);
  fprintf(stderr, "rotleap: unknown command '%s' (try rotleap --help)\n", cmd);
  return 2;
}
