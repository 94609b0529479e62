/* The blow-up and drift watch of the run driver (run.h). */
#include "rotleap/run.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void rl_watch_init(rl_watch *w)
{
  memset(w, 0, sizeof *w);
  w->prevE = w->T1 = w->T2 = NAN;
}

double rl_watch_kT(const rl_watch *w, const rl_watch_params *p, const rl_system *sys)
{
  const double mean = w->T_n > 0 ? w->T_sum / w->T_n : 0.0;
  const int n = rl_system_count(sys);
  const double floor = w->nev > 0 && n > 0 && isfinite(w->U0) ? 1e-3 * fabs(w->U0) / n : 0.0;
  return fmax(rl_system_kB(sys) * fmax(p->T, mean), floor);
}

double rl_watch_drift(const rl_watch *w, double *sem)
{
  *sem = NAN;
  if (w->nwin < 2) return 0.0;
  const double mean = w->rate_sum / w->nwin, var = (w->rate_sum2 - w->nwin * mean * mean) / (w->nwin - 1);
  *sem = sqrt(fmax(var, 0.0) / w->nwin);
  return mean;
}

int rl_watch_isokinetic_mode(const rl_watch_params *p, double alt) { return p->isokinetic && alt > p->alt_mode; }

static const char *or(const char *name, const char *plain) { return name ? name : plain; }

static int checks(rl_watch *w, const rl_watch_params *p, const rl_system *sys, const rl_step_info *info, long k,
                  long every, double h)
{
  const int ev = every <= 1 || k % every == 0;
  const int n = rl_system_count(sys);
  const char *tu = rl_system_units(sys) == RL_UNITS_REAL ? "ps" : "reduced";
  const char *dt_name = or(p->names.timestep, "the time step");
  if (ev && w->nev++ == 0) w->U0 = info->potential;
  const double kT = rl_watch_kT(w, p, sys);
  /* a blow-up within the first steps of a start whose energy was far above a liquid's points at
   * overlapping molecules more than at the time step */
  char hint[512] = "";
  const double u0 = kT > 0 ? w->U0 / (n * kT) : 0.0;
  if (w->nev <= 20 && !(u0 <= 5.0))
    snprintf(hint, sizeof hint, "; the start's U/N was %.3g kT (a liquid's is negative): overlapping molecules "
             "are the likelier cause: lower the density, or relax the start (%s)", u0,
             or(p->names.relax, "a relaxation at a small time step"));
  if (ev) { /* on the steps with energies: compared with the previous such step */
    double prevE = w->prevE;
    w->prevE = info->total;
    if (!isfinite(info->total))
      return rl_error(RL_ENONFINITE, "step %ld (t = %g %s): the total energy is not finite: the run blew up; "
                      "reduce %s (now %g)%s", k, info->t, tu, dt_name, h, hint);
    double jump = fabs(info->total - prevE);
    if (isfinite(prevE) && kT > 0 && jump > 10.0 * n * kT && !w->relax)
      return rl_error(RL_EINVAL, "step %ld (t = %g %s): the total energy jumped by %.3g %s (more "
                      "than 10 kT per molecule): the run is unstable; reduce %s (now %g)%s", k,
                      info->t, tu, jump, every > 1 ? "since its last evaluation" : "in one step",
                      dt_name, h, hint);
  }
  double L[3];
  rl_system_box(sys, L);
  const double Lmin = fmin(L[0], fmin(L[1], L[2]));
  for (int i = 0; i < n; i++) {
    double v[3];
    rl_system_get_velocity(sys, i, v);
    double step = h * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(step <= Lmin))
      return rl_error(RL_EINVAL, "step %ld (t = %g %s): molecule %d moved %.3g in one step, more than the "
                      "box edge %.3g: the run blew up; reduce %s (now %g)%s", k, info->t, tu, i,
                      step, Lmin, dt_name, h, hint);
  }
  if (w->relax) return RL_OK;
  /* the step-to-step alternation of the temperature, on every step: the isokinetic scheme's
   * period-2 mode (rl_watch_isokinetic_mode) */
  if (isfinite(w->T2)) {
    w->alt_sum += 0.25 * fabs(info->temperature - 2.0 * w->T1 + w->T2);
    w->alt_n++;
  }
  w->T2 = w->T1;
  w->T1 = info->temperature;
  if (!ev) return RL_OK;
  if (!w->open) {
    w->open = 1;
    w->step0 = k;
    w->t0 = info->t;
    w->c0 = info->conserved;
    w->alt_sum = 0.0;
    w->alt_n = 0;
  } else if (k - w->step0 >= 50 && info->t - w->t0 >= p->window && kT > 0) {
    double rate = (info->conserved - w->c0) / (n * kT * (info->t - w->t0));
    w->rate_sum += rate;
    w->rate_sum2 += rate * rate;
    w->nwin++;
    const double alt = w->alt_n > 0 && p->T > 0 ? w->alt_sum / w->alt_n / p->T : 0.0;
    if (fabs(rate) > fabs(w->max_rate)) {
      w->max_rate = rate;
      w->alt_at_max = alt;
    }
    w->open = 0;
    /* the isokinetic scheme's sum is not an exact invariant (integrator.h), but a sound run keeps
     * it flat (rl at 10 fs); Fincham's isokinetic run at 4 fs drifted 7 kT per molecule per ps
     * while T_trans fell to 231 K and T_rot rose to 468 K (bench/paper): it stops too.  A start far
     * from the thermostat's temperature drifts at any step: then the message says so */
    if (fabs(rate) > p->drift_error && rl_watch_isokinetic_mode(p, alt))
      return rl_error(RL_EINVAL, "step %ld (t = %g %s): the conserved energy drifted by %.3g kT per molecule per "
                      "%s over the last %g %s (more than %g): this is the isokinetic thermostat, not the time step: "
                      "eqs. 17-18 hold only the on-step temperature at the thermostat's, and the kinetic energy "
                      "alternates from step to step by +-%.2g %% of it, a mode the scheme never damps, excited by a "
                      "start out of equilibrium at that temperature; reducing %s does not remove it.  %s", k, info->t,
                      tu, rate, tu, info->t - w->t0, tu, p->drift_error, 100.0 * alt, dt_name,
                      or(p->names.isokinetic, "Relax the start at the thermostat's temperature first, or use Bussi's "
                                              "thermostat"));
    if (fabs(rate) > p->drift_error)
      return rl_error(RL_EINVAL, "step %ld (t = %g %s): the conserved energy drifted by %.3g kT per molecule per "
                      "%s over the last %g %s (more than %g): integration error is %s the system; reduce %s "
                      "(now %g)", k, info->t, tu, rate, tu, info->t - w->t0, tu, p->drift_error,
                      rate > 0 ? "heating" : "cooling", dt_name, h);
  }
  return RL_OK;
}

int rl_watch_step(rl_watch *w, const rl_watch_params *p, const rl_system *sys, const rl_step_info *info, long k,
                  long every, double h)
{
  const int st = checks(w, p, sys, info, k, every, h);
  /* the temperatures seen so far, for the scale of the next steps' checks (not this one's: a
   * blow-up's temperature must not excuse its own energy jump) */
  if (!st && isfinite(info->temperature)) {
    w->T_sum += info->temperature;
    w->T_n++;
  }
  return st;
}
