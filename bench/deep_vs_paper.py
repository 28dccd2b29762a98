"""The paper-depth scene against the paper scene itself (issue 26, item 3; not a test).

The `deep` scene meshes the central 20 m of paper ridge N's pile on 0.15 m
elements. What the narrower domain and the coarser mesh cost is measured here
on the same ridge: each variant runs ridge N's pile (cut to its width) at the
paper's reference set-up (mu 0.3, the pile's own friction, tau_cr 50 kPa) with
the study's `fast` numerics to 20 mm, and is compared with the paper scene's
run on the first (cohesive) peak F^m and y_I at it, alpha and A_p over
y_I = 1...20 mm (split bond points, docs/postproc.md), F(20 mm) and the cost.

    OMP_NUM_THREADS=2 /usr/bin/python3 bench/deep_vs_paper.py [--ridges 1 2]
        [--variants paper deep deep_h0.2 deep_w12 deep_w30 deep_w50_h0.2 deep_w50] [--settle-bonds checked|held]
        [--side-walls free|held]
        [--out-dir runs/bench/deep_vs_paper] [--study-dir runs/deep]

Variants (domain width, element size): paper (50 m, 0.085 m), deep (20 m,
0.15 m: the study's scene; the run is data/study_deep_direction.table's line of that
name, made by whichever of the two comes first), deep_h0.2 (20 m, 0.2 m), deep_w12 (12 m, 0.15 m),
deep_w30 (30 m, 0.15 m), deep_w50_h0.2 (the paper scene's whole 50 m, nothing cut, on 0.2 m
elements: about as many triangles as deep_w30), deep_w50 (the whole 50 m on 0.15 m elements).
What each cost is in its row (bench/README.md): the paper
scene takes hours, a deep variant tens of minutes. Runs are kept in --out-dir (the deep one in the
study's folder, --study-dir) and resumed from their
checkpoints (run the script again); every row is written to
bench/results/deep_vs_paper.json as soon as its run exists.

--side-walls held holds the blocks where phase 1's walls stood in an uncropped
scene (paper, deep_w50*), as a cropped scene's cut faces are held: ridge 2's
paper scene was not at rest after 5 s with them free (docs/study_paper_depth.md).
"""
import argparse
import json
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from icerubble import machine  # noqa: E402
from icerubble import parameters as P  # noqa: E402
from icerubble.files import results  # noqa: E402
from icerubble.run import presets  # noqa: E402
from icerubble.study.line import run_one  # noqa: E402
from postproc import failure_plane, loads, plug  # noqa: E402

OUT_JSON = os.path.join(ROOT, "bench", "results", "deep_vs_paper.json")
TRAVEL = 20e-3                      # m: the paper's "after the steep decrease" instant
FIRST_PEAK_TRAVEL = 1e-3            # m: the first peak, before a later event in the 5 mm window can replace it
# as data/study_deep_direction.table's line: the scenes were compared with eq 11 as printed,
# the default when they were measured (bench/results/deep_vs_paper.json)
REFERENCE = dict(mu=0.3, tau_cr=50e3, target_travel=TRAVEL, force_direction="paper")
SETTLE_BONDS = P.REGISTRY["settle_bonds"].choices   # the study's tables check them ('checked')
SIDE_WALLS = P.REGISTRY["side_walls"].choices
# (domain width m, element size m) of the variants beside the two scenes
EXTRA = {"deep_h0.2": (20.0, 0.2), "deep_w12": (12.0, 0.15), "deep_w30": (30.0, 0.15),
         # the whole domain, so no cut face at all: what the width costs, paid for by the mesh
         "deep_w50_h0.2": (50.0, 0.2), "deep_w50": (50.0, 0.15)}
ORDER = ("deep", "deep_h0.2", "deep_w12", "deep_w30", "deep_w50_h0.2", "deep_w50", "paper")   # cheap first


def register_variants():
    """The extra variants as scenes of this process only (not the project's)."""
    for name, (width, h) in EXTRA.items():
        presets.SCENES[name] = dict(presets.SCENES["deep"], domain_width=width, element_size=h)
        presets.NUMERICS[name] = presets.NUMERICS["deep"]


def measures(path):
    r = results.load(path)
    y, F = r.force_y, r.force_F
    F_m, y_m = loads.cohesive_peak(y, F)
    early = y <= FIRST_PEAK_TRAVEL
    i_first = int(np.argmax(np.where(early, F, -np.inf)))
    alpha_mean, alpha_sd = failure_plane.mean_sd(failure_plane.alpha_samples(r))
    areas = [plug.plug_area(r, t) for t in failure_plane.ALPHA_TRAVELS]
    a = r.attrs
    return dict(F_m_kN_per_m=F_m / 1e3, y_I_peak_mm=y_m * 1e3,
                first_peak_kN_per_m=float(F[i_first]) / 1e3, y_I_first_peak_mm=float(y[i_first]) * 1e3,
                n_split_settle=int(np.sum(r.bonds["t_split"] < 0)) if "t_split" in r.bonds else 0,
                settle_bonds=str(r.parameters.get("settle_bonds", P.REGISTRY["settle_bonds"].default)),
                side_walls=str(r.parameters.get("side_walls", P.REGISTRY["side_walls"].default)),
                settle_indenter=str(r.parameters.get("settle_indenter", P.REGISTRY["settle_indenter"].default)),
                F_20mm_kN_per_m=loads.load_at(y, F, TRAVEL) / 1e3,
                alpha_mean_1_20mm_deg=alpha_mean, alpha_sd_1_20mm_deg=alpha_sd,
                A_p_mean_1_20mm_m2=failure_plane.mean_sd(areas)[0],
                keel_depth_m=r.keel_depth, porosity=r.porosity,
                n_triangles=int(len(r.elem_area)), dt_s=float(r.parameters.get("dt", np.nan)),
                settle_time_s=float(a.get("settle_time", np.nan)),
                wall_settle_s=float(a.get("wall_settle_s", np.nan)),
                wall_load_s=float(a.get("wall_load_s", np.nan)),
                load_steps=int(a.get("load_steps", 0)), code_version=str(a.get("code_version", "")))


def main(argv=None):
    ap = argparse.ArgumentParser(prog="bench/deep_vs_paper.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ridges", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--variants", nargs="+", choices=ORDER, default=["deep", "paper"])
    ap.add_argument("--out-dir", default=os.path.join(ROOT, "runs", "bench", "deep_vs_paper"))
    # the study's folder: its deep_ridgeN_mu0.3_tau50k line is this bench's deep run
    ap.add_argument("--study-dir", default=os.path.join(ROOT, "runs", "deep"))
    ap.add_argument("--settle-bonds", choices=SETTLE_BONDS, default="checked",
                    help="the bonds while settling: checked (the study's tables) or held (every bond "
                         "kept while settling, the earlier reference); a held run's name ends in _held")
    ap.add_argument("--side-walls", choices=SIDE_WALLS, default="free",
                    help="an uncropped scene's ends: free (no walls after phase 1) or held where phase 1's "
                         "walls stood; a held run's name ends in _walls")
    ap.add_argument("--measure", nargs="+", metavar="VARIANT=RESULT.h5",
                    help="measure these finished runs (of --ridges' first ridge) instead of running "
                         "(runs made in another checkout)")
    a = ap.parse_args(argv)
    register_variants()
    rows = []
    if os.path.exists(OUT_JSON):   # rows of other ridges and variants measured before
        with open(OUT_JSON) as f:
            rows = [r for r in json.load(f)["runs"]
                    if a.measure or key(r) not in {(g, v, a.settle_bonds, a.side_walls)
                                                   for g in a.ridges for v in a.variants}]
    if a.measure:
        for item in a.measure:
            name, path = item.split("=", 1)
            if name not in ORDER:
                raise SystemExit(f"--measure: {name!r} is not a variant ({', '.join(ORDER)})")
            row = dict(ridge=a.ridges[0], variant=name, file=path, **measures(path))
            rows = [r for r in rows if key(r) != key(row)]
            rows.append(row)
        write(rows)
        report(rows)
        return
    held = a.settle_bonds != "checked"
    walls = a.side_walls != "free"
    for ridge in a.ridges:
        for name in [v for v in ORDER if v in a.variants]:
            out = run_one(name, ridge, overrides=dict(REFERENCE, settle_bonds=a.settle_bonds, side_walls=a.side_walls),
                          numerics_name="fast",
                          out_dir=a.study_dir if name == "deep" and not (held or walls) else a.out_dir,
                          # data/study_deep_direction.table's name, for the study's settling
                          description=(f"{name}_ridge{ridge}_mu0.3_tau50k" + ("_held" if held else "")
                                       + ("_walls" if walls else "")))
            rows.append(dict(ridge=ridge, variant=name, file=os.path.relpath(out, ROOT), **measures(out)))
            write(rows)
    report(rows)


def key(row):
    """A row's run: ridge, variant, the bonds while settling and the side
    walls (rows measured before a column: checked, free, as the study's tables)."""
    return row["ridge"], row["variant"], row.get("settle_bonds", "checked"), row.get("side_walls", "free")


def order(row):
    ridge, variant, bonds, walls = key(row)
    return ridge, ORDER.index(variant), SETTLE_BONDS.index(bonds), SIDE_WALLS.index(walls)


def write(rows):
    os.makedirs(os.path.dirname(OUT_JSON), exist_ok=True)
    with open(OUT_JSON + ".part", "w") as f:
        json.dump(dict(set_up=dict(REFERENCE, numerics="fast"), machine=machine.processor(),
                       runs=sorted(rows, key=order)),
                  f, indent=1, default=float)
    os.replace(OUT_JSON + ".part", OUT_JSON)


def report(rows):
    keys = ("F_m_kN_per_m", "y_I_peak_mm", "alpha_mean_1_20mm_deg", "A_p_mean_1_20mm_m2", "F_20mm_kN_per_m")
    for r in sorted(rows, key=order):
        ref = next((q for q in rows if key(q)[:3] == (r["ridge"], "paper", "checked")), None)
        vals = "  ".join(f"{k.split('_')[0]} {r[k]:8.3f}" + (f" ({100 * (r[k] / ref[k] - 1):+5.1f} %)" if ref else "")
                         for k in keys)
        print(f"ridge {r['ridge']} {r['variant']:10s} {key(r)[2]:7s} {key(r)[3]:5s} {vals}  "
              f"{r['n_triangles']} triangles, "
              f"load {r['wall_load_s'] / 60:.1f} min")


if __name__ == "__main__":
    main()
