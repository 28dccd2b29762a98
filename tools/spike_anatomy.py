"""Anatomy of the late force spikes of a punch-through run (issue 26, item 6).

    /usr/bin/python3 tools/spike_anatomy.py table RESULT.h5 [...]
        one markdown row per run: the cohesive peak (max F over 0-2 mm), the
        events beyond 2 mm above it (count, the largest as a multiple of the
        peak), the record maximum, the lowest F beyond 2 mm, the ledger's
        largest |residual| and contact term against the boundary work, and
        the bond points that split in the 5 ms before the record maximum.

    /usr/bin/python3 tools/spike_anatomy.py summary RESULT.h5 [...]
        first peak (max F over 0-5 mm), record maximum beyond 5 mm, the events
        beyond 5 mm above the first peak, and the energy ledger and bond
        failures around the record maximum.

    OMP_NUM_THREADS=1 /usr/bin/python3 tools/spike_anatomy.py run --ridge 1 --mu 0.05 --tau 1e5 \\
            --out DIR [--scene small] [--penalty P] [--every-mm 1] [--keep-from-mm 0] [--settle-bonds checked]
            [--numerics fast] [--force-direction paper|work_conjugate] [--settle-max-time S]
        one run as `icerubble study run` makes it (run_one: same scene,
        numerics, shared rest state), which also keeps a copy of the
        checkpoint every --every-mm of travel (DIR/<name>_ckpts/y<mm>.h5) and
        a diagnostic row per force sample (DIR/<name>_diag.npz).

    OMP_NUM_THREADS=1 /usr/bin/python3 tools/spike_anatomy.py window CKPT.h5 --to-mm Y \\
            --out OUT.npz [--every-steps 20] [--dt-factor 1]
        continue a kept checkpoint to travel Y with dense sampling: the
        instantaneous indenter force, the energy ledger, the indenter's
        contacts per partner body (force, penalty energy, overlap area, from
        the engine's pair kernel), the body with the most kinetic energy, and
        the bond events of the window. --dt-factor < 1 reruns the window at a
        smaller step (the stability check).
"""
import argparse
import json
import math
import os
import shutil
import sys

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from icerubble import parameters as P  # noqa: E402
from icerubble import _engine  # noqa: E402
from icerubble.run import checkpoint as ckpt  # noqa: E402
from icerubble.run import run_identity as RI  # noqa: E402
from icerubble.run.presets import DEFAULT_NUMERICS, numerics, scene  # noqa: E402
from icerubble.run.punch_through_run import PunchThrough, RunOptions  # noqa: E402
from icerubble.files.recorder import ENERGY_TERMS  # noqa: E402
from icerubble.run.scene_cache import scene_files  # noqa: E402
from icerubble.files.mesh_file import read_mesh  # noqa: E402
from icerubble.study.line import run_name  # noqa: E402

FIRST_PEAK_TRAVEL = 5e-3


# ---------------------------------------------------------------- summary
def events_above(y, F, late, peak):
    """Runs of `late` samples whose F lies above `peak`: (first y, last y, max F) each."""
    above = late & (F > peak)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], above.astype(int), [0]))))
    return [(y[a], y[b - 1], F[a:b].max()) for a, b in zip(edges[::2], edges[1::2])]


def summarize(path, window_mm=1.0):
    with h5py.File(path, "r") as f:
        fr = {k: f["force"][k][...] for k in f["force"]}
        en = {k: f["energy"][k][...] for k in f["energy"]} if "energy" in f else {}
        bonds = {k: f["bonds"][k][...] for k in f["bonds"]} if "bonds" in f else {}
    y, F = fr["y_I"], fr["F"]
    early = y <= FIRST_PEAK_TRAVEL
    i1 = int(np.argmax(np.where(early, F, -np.inf)))
    late = ~early
    out = dict(file=os.path.basename(path), first_peak=F[i1], y_first=y[i1])
    if late.any():
        i2 = int(np.argmax(np.where(late, F, -np.inf)))
        out.update(late_max=F[i2], y_late=y[i2], late_min=F[late].min(),
                   y_late_min=y[late][np.argmin(F[late])])
        out["events"] = events_above(y, F, late, F[i1])
    else:
        i2 = i1
    print(f"{out['file']}: first peak {out['first_peak'] / 1e3:.1f} kN/m at {out['y_first'] * 1e3:.2f} mm; "
          + (f"late max {out['late_max'] / 1e3:.1f} kN/m at {out['y_late'] * 1e3:.2f} mm, late min "
             f"{out['late_min'] / 1e3:.1f} kN/m at {out['y_late_min'] * 1e3:.2f} mm; "
             f"{len(out['events'])} events above the first peak: "
             + ", ".join(f"{a * 1e3:.2f}-{b * 1e3:.2f} mm max {m / 1e3:.1f}" for a, b, m in out["events"])
             if "late_max" in out else ""))
    yc = y[i2]
    w = np.abs(y - yc) <= window_mm * 1e-3
    print("  force record around the late maximum (y_I mm, F kN/m, F_instant kN/m):")
    Fi = fr.get("F_instant", np.full_like(F, np.nan))
    for k in np.flatnonzero(w):
        print(f"    {y[k] * 1e3:7.3f} {F[k] / 1e3:9.2f} {Fi[k] / 1e3:9.2f}")
    if en:
        te = en["t"]
        ye = np.interp(te, fr["t"], y)
        we = np.abs(ye - yc) <= 2 * window_mm * 1e-3
        print("  energy ledger [J/m] around it (y_I mm, " + ", ".join(ENERGY_TERMS) + "):")
        for k in np.flatnonzero(we):
            print(f"    {ye[k] * 1e3:7.3f} " + " ".join(f"{en[t][k]:10.3g}" for t in ENERGY_TERMS if t in en))
    if bonds:
        yf = bonds.get("y_I_fail")
        ys = bonds.get("y_I_split")
        near_f = np.flatnonzero(np.abs(yf - yc) <= window_mm * 1e-3) if yf is not None else []
        near_s = np.flatnonzero(np.abs(ys - yc) <= window_mm * 1e-3) if ys is not None else []
        print(f"  bonds: {np.isfinite(ys).sum()} split, {np.isfinite(yf).sum()} failed in all; within "
              f"{window_mm} mm of the late maximum {len(near_s)} split, {len(near_f)} failed")
        for k in near_f:
            print(f"    failed at {yf[k] * 1e3:.3f} mm: point {k} at ({bonds['position'][k][0]:.2f}, "
                  f"{bonds['position'][k][1]:.2f}) m, bodies {tuple(bonds['bodies'][k])}, mode {bonds['mode'][k]}")
    return out


# ---------------------------------------------------------------- table
COHESIVE_TRAVEL = 2e-3  # docs/force_spikes.md: the cohesive peak is the max over 0-2 mm
BEFORE_MAX_S = 5e-3     # bond splits this long before the record maximum (the ledger's sampling)

TABLE_HEAD = ("| run | cohesive peak (kN/m at mm) | events beyond 2 mm above it | largest / peak | "
              "record max (kN/m at mm) | lowest F beyond 2 mm | max abs(residual) / boundary work | "
              "max abs(contact term) / boundary work | splits in the 5 ms before the record max (x, y extent, m) | "
              "kinetic energy across it (J/m) |\n|" + "---|" * 10)


def table_row(path):
    with h5py.File(path, "r") as f:
        fr = {k: f["force"][k][...] for k in f["force"]}
        en = {k: f["energy"][k][...] for k in f["energy"]}
        bonds = {k: f["bonds"][k][...] for k in ("t_split", "position")}
    y, F, t = fr["y_I"], fr["F"], fr["t"]
    early = y <= COHESIVE_TRAVEL
    i1 = int(np.argmax(np.where(early, F, -np.inf)))
    im = int(np.argmax(F))
    late = ~early
    events = [m for _, _, m in events_above(y, F, late, F[i1])]
    work = max(abs(en["work_boundary"][-1]), 1e-300)
    ts, pos = bonds["t_split"], bonds["position"]
    near = np.flatnonzero((ts > t[im] - BEFORE_MAX_S) & (ts <= t[im]))
    extent = (f"{len(near)} ({np.ptp(pos[near, 0]):.2f} × {np.ptp(pos[near, 1]):.2f} m)" if len(near) else "0")
    te = en["t"]
    kb, ka = np.searchsorted(te, t[im]) - 1, np.searchsorted(te, t[im] + BEFORE_MAX_S)
    kinetic = (f"{en['kinetic'][max(kb, 0)]:.3g} → {en['kinetic'][min(ka, len(te) - 1)]:.3g}")
    return (f"| {os.path.basename(path).replace('.h5', '')} | {F[i1] / 1e3:.1f} at {y[i1] * 1e3:.2f} | {len(events)} | "
            f"{(max(events) / F[i1]) if events else float('nan'):.2f} | {F[im] / 1e3:.1f} at {y[im] * 1e3:.2f} | "
            f"{F[late].min() / 1e3:.1f} | {np.abs(en['residual']).max() / work:.1e} | "
            f"{np.abs(en['contact']).max() / work:.1e} | {extent} | {kinetic} |")


# ---------------------------------------------------------------- diagnostics
class Probe:
    """Per-sample diagnostics of a PunchThrough's model."""

    def __init__(self, run):
        self.run = run
        sc = run.scene
        self.ind_body = int(sc.indenter_bodies[0])
        self.node_body = run.settler.node_body
        self.penalty = run.params["penalty"]
        self.rows = []

    def _indenter_contacts(self, m):
        """The indenter's contacts per partner body from the engine's pair kernel:
        vertical force on the indenter [N/m], penalty energy [J/m], the largest
        overlap area [m^2] of a triangle pair."""
        tri = np.asarray(m.triangles)
        body = np.asarray(m.body)
        x = np.asarray(m.positions)
        surf = np.asarray(m.surface_triangles)
        ind = surf[body[surf] == self.ind_body]
        oth = surf[body[surf] != self.ind_body]
        pi, po = x[tri[ind]], x[tri[oth]]
        lo_i, hi_i = pi.min(axis=1), pi.max(axis=1)
        lo_o, hi_o = po.min(axis=1), po.max(axis=1)
        box_lo, box_hi = lo_i.min(axis=0), hi_i.max(axis=0)
        near = np.all((hi_o >= box_lo) & (lo_o <= box_hi), axis=1)
        per = {}
        max_area = 0.0
        for jo in np.flatnonzero(near):
            hit = np.all((hi_i >= lo_o[jo]) & (lo_i <= hi_o[jo]), axis=1)
            for ji in np.flatnonzero(hit):
                r = _engine.contact_pair(pi[ji], po[jo], self.penalty)
                r2 = _engine.contact_pair(po[jo], pi[ji], self.penalty)
                fy = 0.0
                e = a = 0.0
                if r is not None:
                    fy += float(np.sum(r["forces"][:3, 1]))
                    e += 0.5 * r["energy"]
                    a = max(a, r["area"])
                if r2 is not None:
                    fy += float(np.sum(r2["forces"][3:, 1]))
                    e += 0.5 * r2["energy"]
                    a = max(a, r2["area"])
                if r is None and r2 is None:
                    continue
                b = int(body[oth[jo]])
                s = per.setdefault(b, [0.0, 0.0, 0.0, 0])
                s[0] += fy
                s[1] += e
                s[2] = max(s[2], a)
                s[3] += 1
                max_area = max(max_area, a)
        return per, max_area

    def sample(self, t_rel, y_I, F, F_now, contacts=True):
        m = self.run.model
        e = m.energies()
        v = np.asarray(m.velocities)
        mass = np.asarray(m.mass)
        tri, body = np.asarray(m.triangles), np.asarray(m.body)
        nb = np.full(m.n_nodes, -1, np.int64)   # a node's body (split nodes included): its last triangle's
        nb[tri.ravel()] = np.repeat(body, 3)
        ok = nb >= 0
        ke_body = np.bincount(nb[ok], weights=0.5 * mass[ok] * (v[ok] ** 2).sum(axis=1),
                              minlength=len(self.run.scene.body_kind))
        kb = int(np.argmax(np.where(np.arange(len(ke_body)) == self.ind_body, -1, ke_body)))
        fc = np.asarray(m.forces("contact"))
        ind_nodes = m.node_sets["indenter"]
        row = dict(t=t_rel, y_I=y_I, F=F, F_now=F_now, **{f"E_{k}": e[k] for k in ENERGY_TERMS},
                   E_contact_solver=e.get("contact_solver", np.nan), E_friction_solver=e.get("friction_solver", np.nan),
                   contact_on_indenter_y=float(-fc[ind_nodes, 1].sum()),
                   max_node_contact=float(np.sqrt((fc ** 2).sum(axis=1)).max()),
                   ke_max_body=kb, ke_max=float(ke_body[kb]), v_max=float(np.sqrt((v ** 2).sum(axis=1)).max()))
        if contacts:
            per, amax = self._indenter_contacts(m)
            top = sorted(per.items(), key=lambda kv: kv[1][0])[:4]   # most upward push on... most negative fy
            row.update(ind_contact_area_max=amax,
                       ind_contact_energy=sum(s[1] for s in per.values()),
                       ind_partners=json.dumps({int(b): [round(-s[0], 1), s[1], s[2], s[3]] for b, s in top}))
        self.rows.append(row)
        return row

    def save(self, path, extra=None):
        keys = [k for k in self.rows[0] if k != "ind_partners"]
        arrays = {k: np.array([r.get(k, np.nan) for r in self.rows]) for k in keys}
        if "ind_partners" in self.rows[0]:
            arrays["ind_partners"] = np.array([r["ind_partners"] for r in self.rows])
        arrays.update(extra or {})
        np.savez_compressed(path, **arrays)


def make_run(scene_name, ridge, overrides, out_dir, description=None, numerics_name=None, settle_max_time=None):
    """A PunchThrough set up as run_one sets it up (same identity, shared rest state).
    settle_max_time: as `icerubble study run --settle-max-time` (a settle option,
    so in the shared rest state's key: a line run with it is continued with it)."""
    sc = scene(scene_name)
    settings = numerics(scene_name, numerics_name)
    params = P.validate(dict(sc["params"], **overrides))
    description = description or run_name(scene_name, ridge, params)
    out = os.path.join(out_dir, description + ".h5")
    _, mesh_path = scene_files(scene_name, ridge, root=out_dir)
    if "dt" in overrides:
        settings["dt_fraction"] = None
    extra = {} if settle_max_time is None else dict(settle_max_time=settle_max_time)
    options = RunOptions.from_numerics(settings, name=numerics_name or DEFAULT_NUMERICS, threads=1, **extra)
    ident = RI.identity(params, read_mesh(mesh_path), options)
    run = PunchThrough(mesh_path, out, params=params, options=options,
                       meta=dict(ridge=f"{scene_name}-{int(ridge)}", seed=int(ridge), model="fem-dem",
                                 scene=scene_name, run_id=RI.run_id(ident), run_identity=RI.to_json(ident)),
                       rest_dir=os.path.dirname(mesh_path))
    return run, out


def cmd_run(a):
    overrides = dict(mu=a.mu, tau_cr=a.tau, target_travel=a.travel_mm * 1e-3)
    if a.settle_bonds:
        overrides["settle_bonds"] = a.settle_bonds
    if a.penalty:
        overrides["penalty"] = a.penalty
    if a.force_direction:
        overrides["force_direction"] = a.force_direction
    run, out = make_run(a.scene, a.ridge, overrides, a.out, a.description, numerics_name=a.numerics,
                        settle_max_time=a.settle_max_time)
    probe = Probe(run)
    kept = out[:-3] + "_ckpts"
    os.makedirs(kept, exist_ok=True)
    state = dict(next_mm=max(a.every_mm, a.keep_from_mm))
    force0 = run.recorder.force

    def force(t, y_I, F, F_instant=None):
        force0(t, y_I, F, F_instant)
        if run.state.phase != "load" or y_I <= 0.0:
            return
        probe.sample(t, y_I, F, F_instant if F_instant is not None else F, contacts=a.contacts)
        if y_I * 1e3 >= state["next_mm"]:
            ckpt.save(run, os.path.join(kept, f"y{state['next_mm']:06.2f}.h5"))
            state["next_mm"] += a.every_mm

    run.recorder.force = force
    run.run(resume=False)
    probe.save(out[:-3] + "_diag.npz")
    print("RESULT", out, flush=True)
    summarize(out)


def cmd_window(a):
    with h5py.File(a.checkpoint, "r") as f:
        params = json.loads(f["driver"].attrs["params"])
        meta_scene = a.scene
    # the run whose checkpoint this is: same scene files, parameters, options
    ridge = a.ridge
    scratch = os.path.join(os.path.dirname(os.path.abspath(a.out)), "window_tmp")
    os.makedirs(scratch, exist_ok=True)
    sc = scene(meta_scene)
    settings = numerics(meta_scene, a.numerics)
    _, mesh_path = scene_files(meta_scene, ridge, root=a.scene_root)
    options = RunOptions.from_numerics(settings, name=a.numerics or DEFAULT_NUMERICS, threads=1)
    over = {k: v for k, v in params.items() if k in P.TABLE_1}
    run = PunchThrough(mesh_path, os.path.join(scratch, "w.h5"), params=dict(sc["params"], **over), options=options)
    ckpt.restore(run, a.checkpoint)
    m = run.model
    dt0 = m.dt
    if a.dt_factor != 1.0:
        m.set(dt=dt0 * a.dt_factor)
    if a.penalty:
        m.set(penalty=a.penalty)
    probe = Probe(run)
    probe.penalty = a.penalty or run.params["penalty"]
    ev0 = m.bonds.events()
    n = max(1, int(round(a.every_steps / a.dt_factor)))
    w_prev, y_prev = m.energies()["work_boundary"], run.travel()
    b_prev = run.scene.indenter_net_buoyancy()
    while run.travel() < a.to_mm * 1e-3:
        m.step(n)
        y = run.travel()
        w = m.energies()["work_boundary"]
        b = run.scene.indenter_net_buoyancy()
        F = (w - w_prev) / (y - y_prev) - 0.5 * (b + b_prev) if y - y_prev > 1e-12 else math.nan
        w_prev, y_prev, b_prev = w, y, b
        probe.sample(m.time - run.state.t_load, y, F, run.scene.indenter_force(), contacts=a.contacts)
    ev = m.bonds.events()
    new_split = np.isfinite(ev["t_split"]) & ~np.isfinite(ev0["t_split"])
    new_fail = np.isfinite(ev["t_fail"]) & ~np.isfinite(ev0["t_fail"])
    extra = dict(dt=m.dt, dt0=dt0, penalty=probe.penalty, t_load=run.state.t_load,
                 split_id=np.flatnonzero(new_split), split_t=ev["t_split"][new_split] - run.state.t_load,
                 split_x=ev["x_split"][new_split], split_y=ev["y_split"][new_split],
                 fail_id=np.flatnonzero(new_fail), fail_t=ev["t_fail"][new_fail] - run.state.t_load,
                 fail_x=ev["x_fail"][new_fail], fail_y=ev["y_fail"][new_fail], fail_mode=ev["mode"][new_fail],
                 stable=json.dumps({k: (v if isinstance(v, str) else float(v) if np.isscalar(v) else None)
                                    for k, v in m.stable_time_step().items()}))
    probe.save(a.out, extra)
    r = probe.rows
    k = int(np.argmax([x["F_now"] for x in r]))
    print(f"window {a.checkpoint} -> {a.to_mm} mm, dt {m.dt:.3g} s (x{a.dt_factor}), penalty {probe.penalty:g}: "
          f"{len(r)} samples; max F_now {r[k]['F_now'] / 1e3:.1f} kN/m at {r[k]['y_I'] * 1e3:.3f} mm "
          f"(t {r[k]['t']:.5f} s); min F_now {min(x['F_now'] for x in r) / 1e3:.1f} kN/m; "
          f"max mean F {np.nanmax([x['F'] for x in r]) / 1e3:.1f} kN/m; {new_split.sum()} splits, "
          f"{new_fail.sum()} failures in the window", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    tb = sub.add_parser("table")
    tb.add_argument("results", nargs="+")
    s = sub.add_parser("summary")
    s.add_argument("results", nargs="+")
    s.add_argument("--window-mm", type=float, default=1.0)
    r = sub.add_parser("run")
    r.add_argument("--scene", default="small")
    r.add_argument("--ridge", type=int, required=True)
    r.add_argument("--mu", type=float, required=True)
    r.add_argument("--tau", type=float, required=True)
    r.add_argument("--penalty", type=float, default=None)
    r.add_argument("--numerics", default=None, help="a numerics preset (default: the scene's default; the deep "
                                                   "study's tables run 'fast')")
    r.add_argument("--settle-bonds", choices=("held", "checked"), default=None,
                   help="default: the scene's (the deep study's tables check them)")
    r.add_argument("--travel-mm", type=float, default=40.0)
    r.add_argument("--every-mm", type=float, default=1.0)
    r.add_argument("--keep-from-mm", type=float, default=0.0, help="keep checkpoints from this travel on")
    r.add_argument("--force-direction", choices=P.FORCE_DIRECTIONS, default=None,
                   help="eq 11's form (default: the parameter's default)")
    r.add_argument("--settle-max-time", type=float, default=None,
                   help="as `icerubble study run --settle-max-time`: needed to load a line's shared rest state")
    r.add_argument("--contacts", action="store_true", help="the indenter's contacts per sample (slower)")
    r.add_argument("--description", default=None)
    r.add_argument("--out", required=True)
    w = sub.add_parser("window")
    w.add_argument("checkpoint")
    w.add_argument("--scene", default="small")
    w.add_argument("--ridge", type=int, required=True)
    w.add_argument("--scene-root", required=True, help="the run's out folder (its scenes/ hold the mesh)")
    w.add_argument("--to-mm", type=float, required=True)
    w.add_argument("--every-steps", type=int, default=20)
    w.add_argument("--dt-factor", type=float, default=1.0)
    w.add_argument("--numerics", default=None, help="the run's numerics preset (as its `run --numerics`)")
    w.add_argument("--penalty", type=float, default=None)
    w.add_argument("--no-contacts", dest="contacts", action="store_false")
    w.add_argument("--out", required=True)
    a = ap.parse_args(argv)
    if a.cmd == "table":
        print(TABLE_HEAD)
        for p in a.results:
            print(table_row(p))
    elif a.cmd == "summary":
        for p in a.results:
            summarize(p, a.window_mm)
    elif a.cmd == "run":
        cmd_run(a)
    else:
        cmd_window(a)


if __name__ == "__main__":
    main()
