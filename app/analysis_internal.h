/* The analysis object of app/analysis.c (records, journal) and app/analysis_results.c (the files
 * it writes): shared by those two files only. */
#ifndef ROTLEAP_APP_ANALYSIS_INTERNAL_H
#define ROTLEAP_APP_ANALYSIS_INTERNAL_H

#include "analysis.h"

#include <stdint.h>
#include <stdio.h>

#define MAX_RDF RL_DECK_MAX_RDF
#define RDF_BINS 200

/* The values of a step record, after its time t; under a barostat the NB values of the box after them. */
enum { V_U, V_T, V_TT, V_TR, V_P, V_E, V_EC, V_K, V_F2, V_K2, NV };
enum { B_V, B_RHO, B_LX, B_LY, B_LZ, B_H, NB }; /* volume, density, edges, enthalpy per molecule */

struct analysis {
  const rl_deck *d;
  double box[3];     /* the system's box (a run at constant volume: the same all along); the deck's
                        under a barostat                                                        */
  const rl_molecule *mol;
  int n;
  rl_trace *v[NV];       /* the step series (V_U: U per molecule, V_E: total, V_EC: conserved)   */
  long nstep;            /* step records consumed                                                */
  double t_first, t_last; /* their first and last times                                          */
  rl_trace *M[3], *M2;   /* per sample: the total dipole's components and |M|^2 (dipolar)       */
  long *mark_c;          /* step records consumed before sample k S (k < nmarks): where the
                            samples of the equilibrated part start, on the RDFs' marks           */
  long mark_every;       /* S                                                                    */
  int nmarks;
  int nrdf;
  rl_rdf *rdf[MAX_RDF];
  int rdf_site[MAX_RDF][2], rdf_sp[MAX_RDF][2]; /* output.rdf: each pair's sites and species */
  char rdf_name[MAX_RDF][48];
  /* a mixture (d->nspecies > 1; else nsp = 0): each species' bodies (consecutive), rotational
   * dof per body and name, its temperatures per step (translational, rotational) and whether
   * its bodies carry the vector of P1/P2 (orient) */
  int nsp;
  int sp_first[RL_DECK_MAX_SPECIES], sp_count[RL_DECK_MAX_SPECIES], sp_rot[RL_DECK_MAX_SPECIES];
  int sp_orient[RL_DECK_MAX_SPECIES];
  const char *sp_name[RL_DECK_MAX_SPECIES];
  rl_trace *vs[RL_DECK_MAX_SPECIES][2];
  rl_vec_series *axis, *vel, *omega, *pos;
  double (*unwrapped)[3], (*buf)[3], (*dip)[3]; /* unwrapped: the centres of the last sample */
  rl_species_ff sff[RL_DECK_MAX_SPECIES]; /* each species', d->nspecies of them */
  int dipolar;       /* the molecules have a net dipole: M, its fluctuation, the dielectric constant */
  int orient;        /* the vector of P1/P2: ORIENT_DIPOLE, ORIENT_AXIS or ORIENT_NONE              */
  char orient_text[400]; /* results.txt's orientation_vector: which vector, or n/a and why          */
  int point_dipoles; /* sites with a point dipole: their boundary is dipole_method's */
  long tcf_cap;      /* samples kept for the correlation functions and the MSD (memory bound) */
  long samples;      /* samples taken                                                        */
  unsigned char *rec; /* one record (its largest size)                                        */
  uint32_t *hist;     /* [nrdf][RDF_BINS] one frame's pair counts                             */
  FILE *jfp;          /* the journal, or NULL                                                 */
  char *jpath;
  long jbytes;        /* bytes of the journal written or replayed                             */
  long seq;           /* records written or replayed                                          */
  int jbad;           /* a write failed: the journal is no longer a prefix of the run         */
  int replayed;
  /* output.tconf: the configurational temperature's sums of each sample (forcefield.h) */
  int tconf;
  rl_trace *tc[6];              /* per sample: sum |F|^2, sum lap_r, sum |tau|^2, sum lap_rot, and
                                   the totals sum |F|^2 + |tau|^2, sum lap_r + lap_rot                */
  const rl_forcefield *ff;      /* analysis_set_tconf: the force field the sums use                */
  char tconf_na[RL_FF_TEXT + 64]; /* why the sums cannot be taken (another term), or ""           */
  char tconf_note[3 * RL_FF_TEXT]; /* the force field's discontinuities (the estimator is biased) */
  /* run.barostat: the box's series (B_*), the mass of the density and the barostat's counts */
  int baro;
  rl_trace *b[NB];
  double mass;
  int have_stats;
  rl_barostat_stats stats;
};

/* The correlation functions and the MSD keep whole configurations (four vectors per body and
 * sample), and are computed directly over every time origin: memory grows with the run and
 * time with samples x lags.  A long run (10^7 steps of 216 TIP4P sampled every 10 would need
 * 20 GB) keeps the first RL_TCF_MEMORY bytes' worth of samples, and the lags go to
 * RL_TCF_MAX_LAG samples at most; results.txt says so when that happens.  The RDFs, the
 * dipole fluctuation and the block averages use every sample. */
#define RL_TCF_MEMORY (256.0 * 1024 * 1024)
#define RL_TCF_MAX_LAG 1000
/* Chodera's detection runs on at most this many block means of U (rl_trace_equilibration) */
#define EQUIL_POINTS 1000
/* The self-diffusion's block error: D of this many consecutive parts of the samples */
#define D_BLOCKS 5

enum { ORIENT_DIPOLE, ORIENT_AXIS, ORIENT_NONE };

#endif
