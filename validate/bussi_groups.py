#!/usr/bin/python3
"""Thermostats at a large step: Bussi with one thermostat over every degree of freedom against one
for translation and one for rotation (run.thermostat_groups = all | trans-rot), and Langevin in the
middle of the drift (run.ensemble = nvt-langevin, friction time --langevin-tau), chosen by --variants.

The system, the shared start, the runs, the analysis and the accuracy test are bench/sampling_speed.py's
(imported): 256 TIP4P-RF at 298 K, a rotleap Bussi reference at --ref-fs (1 fs), and runs at --h-fs
(8 fs) with each grouping and --seeds thermostat seeds.  Each run is accurate if |z_U| <= 3 and
z_rdf <= 3 against the reference (sampling_speed.compare).  The table also has the mean on-step
temperatures and the mean temperatures of the mid-step v(t+h/2) and l(t+h/2) that the thermostat
rescales (thermo columns t_trans_mid, t_rot_mid; the mean is over the production's thermo rows).

Run (from the repository root, after building rotleap):
    /usr/bin/python3 validate/bussi_groups.py [--h-fs 8] [--seeds 3] [--tau 0.1] [--jobs 2] [--keep]
        [--variants all,trans-rot] [--langevin-tau 1] [--md validate/bussi_groups.md]
Defaults: 4 ps equilibration + 200 ps production per run, 10 blocks; 7 runs.
The Langevin comparison: --variants trans-rot,langevin --md validate/langevin_8fs.md (about 12 minutes
with --jobs 2; the mid-step temperatures of a Langevin run are those at the middle of the drift).  About 6 minutes on
this 2-core machine with --jobs 2 (the 1 fs reference is most of it).  Writes validate/bussi_groups.md.
"""
import argparse
import concurrent.futures
import os
import shutil
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "bench"))
import sampling_speed as sp  # noqa: E402  (the benchmark's start, frames, comparison)
import nvt_structure as ns  # noqa: E402
import nve_conservation as nc  # noqa: E402

# variant -> (ensemble, extra deck lines): the two Bussi groupings, and Langevin in the middle of the
# drift (run.tau = --langevin-tau, the friction time; OpenMM's LangevinMiddleIntegrator at 1/ps)
VARIANTS = {"all": ("nvt-bussi", ["thermostat_groups = all"]),
            "trans-rot": ("nvt-bussi", ["thermostat_groups = trans-rot"]),
            "langevin": ("nvt-langevin", []),
            # the symplectic NO_SQUISH rotation (Miller et al. 2002) under the same thermostat:
            # is the bias at 8 fs the revised leapfrog's, or any leapfrog's at this step?
            "no-squish": ("nvt-bussi", ["thermostat_groups = trans-rot", "integrator = no-squish"])}


def mean_mid(run, t_from):
    rows = [r for r in run["rows"] if r["t"] > t_from]
    if not rows:
        return float("nan"), float("nan")
    return (sum(r["Tt_mid"] for r in rows) / len(rows), sum(r["Tr_mid"] for r in rows) / len(rows))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--h-fs", type=float, default=8.0)
    ap.add_argument("--ref-fs", type=float, default=1.0)
    ap.add_argument("--seeds", type=int, default=3, help="thermostat seeds per grouping")
    ap.add_argument("--tau", type=float, default=0.1, help="Bussi relaxation time (ps)")
    ap.add_argument("--prod-ps", type=float, default=200.0)
    ap.add_argument("--eq-ps", type=float, default=4.0)
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--keep", action="store_true")
    ap.add_argument("--variants", default="all,trans-rot",
                    help="comma-separated from %s" % ", ".join(VARIANTS))
    ap.add_argument("--langevin-tau", type=float, default=1.0, help="Langevin friction time 1/gamma (ps)")
    ap.add_argument("--md", default=os.path.join(HERE, "bussi_groups.md"))
    args = ap.parse_args()
    GROUPS = tuple(v.strip() for v in args.variants.split(",") if v.strip())
    bad = [g for g in GROUPS if g not in VARIANTS]
    if bad or not GROUPS:
        ap.error("--variants: unknown %s (choose from %s)" % (", ".join(bad) or "(none)", ", ".join(VARIANTS)))
    ns.TAU_LANGEVIN = args.langevin_tau
    rotleap = os.path.abspath(args.rotleap)
    ns.TAU_BUSSI = args.tau
    frame = sp.frame_fs([args.ref_fs, args.h_fs])
    ns.FRAME_PS = frame * 1e-3
    ns.RDF_STRIDE = max(1, int(round(sp.RDF_EVERY_PS / ns.FRAME_PS)))
    eq_frames = int(round(args.eq_ps / ns.FRAME_PS))
    prod_frames = max(1, int(round(args.prod_ps / ns.FRAME_PS / args.blocks))) * args.blocks
    eq_eff = eq_frames * ns.FRAME_PS
    nfr = eq_frames + prod_frames
    every = lambda h: int(round(frame / h))  # noqa: E731
    work = tempfile.mkdtemp(prefix="rotleap-bussi-groups-")
    t0 = time.time()
    ck, v, l, F, K, eqinfo = nc.shared_start(rotleap, work, sp.START_EQ_STEPS)
    base = (rotleap, work, ck, v, l, F, K)
    tasks = [(base + ("nvt-bussi", args.ref_fs * 1e-3, nfr * every(args.ref_fs), every(args.ref_fs)), {},
              ("reference", 0))]
    for g in GROUPS:
        ens, extra = VARIANTS[g]
        for k in range(1, args.seeds + 1):
            tasks.append((base + (ens, args.h_fs * 1e-3, nfr * every(args.h_fs), every(args.h_fs)),
                          dict(extra=extra + ["seed = %d" % k], suffix="_%s_s%d" % (g, k)), (g, k)))
    runs = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futs = {pool.submit(ns.rotleap_task, *a, **kw): key for a, kw, key in tasks}
        for fut in concurrent.futures.as_completed(futs):
            r = fut.result()
            runs[futs[fut]] = r
            print("  %-40s %s, %.0f s" % (r["label"] + " %s" % (futs[fut],), "ok" if not r["rc"] else
                                          "STOPPED: " + r["error"], r["wall_s"]), flush=True)
    t_sim = time.time() - t0
    for r in runs.values():
        r["analysis"] = ns.analyse(r, eq_eff, args.blocks) if not r["rc"] else dict(ok=False)
    ref = runs[("reference", 0)]
    head = ["run", "h (fs)", "seed", "U/N (kJ/mol)", "z_U", "z_rdf", "p", "T_trans", "T_rot", "T_trans mid",
            "T_rot mid", "accurate"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    passed = {g: 0 for g in GROUPS}
    for key in [("reference", 0)] + [(g, k) for g in GROUPS for k in range(1, args.seeds + 1)]:
        r = runs[key]
        a = r["analysis"]
        if not a.get("ok"):
            lines.append("| %s | %g | %d | %s | | | | | | | | no |" % (key[0], r["h_fs"], key[1], r["error"] or "failed"))
            continue
        s = a["scalars"]
        tm = mean_mid(r, eq_eff)
        if key[0] == "reference":
            cells = ["", "", ""]
            ok = "reference"
        else:
            c = sp.compare(r, ref)
            good = abs(c["z_U"]) <= sp.Z_TOL and c["z_rdf"] <= sp.Z_TOL
            passed[key[0]] += good
            cells = ["%.2f" % c["z_U"], "%.2f" % c["z_rdf"], "%.4f" % c["p"]]
            ok = "yes" if good else "no"
        lines.append("| " + " | ".join([key[0], "%g" % r["h_fs"], str(key[1]) if key[1] else "",
                                        "%.3f ± %.3f" % tuple(s["U"])] + cells +
                                       ["%.1f" % s["Tt"][0], "%.1f" % s["Tr"][0], "%.1f" % tm[0], "%.1f" % tm[1], ok])
                     + " |")
    lines.append("")
    lines.append("Accurate runs at %g fs: %s." % (args.h_fs, ", ".join("%s %d of %d" % (g, passed[g], args.seeds)
                                                                     for g in GROUPS)))
    elapsed = time.time() - t0
    print("\n".join(lines))
    cmd = "/usr/bin/python3 validate/bussi_groups.py " + " ".join(sys.argv[1:])
    with open(args.md + ".part", "w") as f:
        f.write("# Thermostats at %g fs: %s (256 TIP4P-RF, 298 K)\n\n" % (args.h_fs, ", ".join(GROUPS)))
        f.write("Generated by `%s` on %s at rotleap %s in %.0f s (simulation %.0f s). Do not edit: rerun the "
                "script. Method: its docstring; the mechanism: docs/integrators.md, \"Bussi thermostat groups\".\n\n"
                % (cmd.strip(), time.strftime("%Y-%m-%d %H:%M"), sp.git_head(), elapsed, t_sim))
        if "langevin" in GROUPS:
            f.write("Langevin (run.ensemble = nvt-langevin): friction time 1/gamma = %g ps; the mid-step "
                    "temperatures are those after the kick, before the Ornstein-Uhlenbeck step.\n\n"
                    % args.langevin_tau)
        f.write("Bussi tau = %g ps; %g ps equilibration + %g ps production per run, %d blocks, frames every %g fs; "
                "reference at %g fs (trans-rot). Temperatures in K: on-step T_trans, T_rot (eqs. 9, 12) and the "
                "mid-step ones the thermostat rescales (before rescaling).\n\n"
                % (args.tau, eq_eff, prod_frames * ns.FRAME_PS, args.blocks, frame, args.ref_fs))
        f.write("\n".join(lines) + "\n")
    os.replace(args.md + ".part", args.md)
    if args.keep:
        print("work directory kept: %s" % work)
    else:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
