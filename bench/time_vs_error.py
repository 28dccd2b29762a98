"""Run time against error: how the time step and the mesh size trade accuracy
for speed. Not a test: prints figures, writes bench/results/time_vs_error.json.

1. Time step: the head-on collision of two 1 m x 0.5 m ice blocks (h = 0.1 m,
   2 m/s closing, penalty 2e11, no friction, damping, gravity or water) at
   dt = f x the engine's stable step, f = 0.1 ... 1. Error: the change of total
   energy (kinetic + elastic) over the impact, which is zero for the exact
   solution; cost: wall time per simulated millisecond.
2. Mesh size: a longitudinal pulse in a slender plane-strain bar; error of the
   measured wave speed against sqrt(E/(rho(1-nu^2))) for h = L/50 ... L/400.

    /usr/bin/python3 bench/time_vs_error.py [--quick]
"""
import json
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
from icerubble import engine

ICE = dict(E=2e9, nu=0.3, rho=920.0, damping=0.0)


def collision(f):
    L, H, h, gap = 1.0, 0.5, 0.1, 1e-3
    na_, ta = engine.rectangle_mesh(int(L / h), int(H / h), h, origin=(-L - gap / 2, 0.0))
    nb_, tb = engine.rectangle_mesh(int(L / h), int(H / h), h, origin=(gap / 2, 0.0))
    nodes, tri = np.r_[na_, nb_], np.r_[ta, tb + len(na_)]
    body = np.r_[np.zeros(len(ta)), np.ones(len(tb))].astype(int)
    m = engine.Model(nodes, tri, body, materials=ICE)
    m.set(gravity=False, water=False, mu=0.0, penalty=2e11, threads=1)
    dt = f * m.stable_time_step()["dt"]
    m.set(dt=dt)
    v = np.zeros((len(nodes), 2))
    v[:len(na_), 0], v[len(na_):, 0] = 1.0, -1.0
    m.set_velocities(v)
    E0 = 0.5 * np.asarray(m.mass).sum()
    T = 3e-3
    t0 = time.perf_counter()
    m.step(int(T / dt))
    wall = time.perf_counter() - t0
    e = m.energies()
    return dict(case="collision", dt_fraction=f, dt=dt, steps=int(T / dt),
                wall_s_per_ms=wall / (T * 1e3),
                energy_error=abs(e["kinetic"] + e["elastic"] + e["contact_solver"] - E0) / E0)


def pulse(n):
    """Bar of length 10 m, height 0.1 m, n cells along: a smooth 1 ms velocity
    pulse at the left end (wavelength 1.7 m, 17 bar heights: lateral inertia
    changes the speed by < 0.1 %); the wave speed from the arrival time of the
    pulse centre at 8 m."""
    L, H, X = 10.0, 0.1, 8.0
    h = L / n
    ny = max(1, int(round(H / h)))
    nodes, tri = engine.rectangle_mesh(n, ny, h, H / ny)
    m = engine.Model(nodes, tri, np.zeros(len(tri), int), materials=ICE,
                   node_sets={"left": np.flatnonzero(nodes[:, 0] == 0.0)})
    m.set(gravity=False, water=False, threads=1)
    dt = 0.5 * m.stable_time_step()["dt"]
    m.set(dt=dt)
    tp = 1e-3
    ts = np.linspace(0, tp, 41)
    m.prescribe_velocity("left", (1, 0), y=False, table=(ts, 1e-3 * np.sin(np.pi * ts / tp) ** 2))
    c = np.sqrt(ICE["E"] / (ICE["rho"] * (1 - ICE["nu"] ** 2)))
    probe = np.flatnonzero(np.isclose(nodes[:, 0], X))
    t0 = time.perf_counter()
    times, vel = [], []
    while m.time < X / c + 2 * tp:
        m.step(5)
        times.append(m.time)
        vel.append(m.velocities[probe, 0].mean())
    wall = time.perf_counter() - t0
    times, vel = np.array(times), np.array(vel)
    peak = vel.max()
    # arrival of the pulse centre: the centroid of the velocity record
    t_c = (times * vel).sum() / vel.sum()
    c_meas = X / (t_c - tp / 2)
    return dict(case="wave", cells=n, h=h, triangles=len(tri), wall_s=wall,
                wave_speed_error=abs(c_meas - c) / c, peak=peak)


def main():
    quick = "--quick" in sys.argv
    rows = [collision(f) for f in ((0.25, 0.5, 1.0) if quick else (0.1, 0.25, 0.5, 0.8, 1.0))]
    rows += [pulse(n) for n in ((50, 100) if quick else (50, 100, 200, 400))]
    print("time step vs energy error (two-block collision, h = 0.1 m, penalty 2e11)")
    print("  dt/stable      dt [s]   wall s per ms simulated   |dE|/E0")
    for r in rows:
        if r["case"] == "collision":
            print(f"  {r['dt_fraction']:9.2f}  {r['dt']:10.3e}  {r['wall_s_per_ms']:24.3f}  {r['energy_error']:.2e}")
    print("mesh size vs wave speed error (plane-strain bar, 10 m, 1 ms pulse)")
    print("  cells   h [m]  triangles   wall s   |c - c0|/c0")
    for r in rows:
        if r["case"] == "wave":
            print(f"  {r['cells']:5d}  {r['h']:.4f}  {r['triangles']:9d}  {r['wall_s']:7.2f}  {r['wave_speed_error']:.2e}")
    out = os.path.join(ROOT, "bench", "results", "time_vs_error.json")
    with open(out, "w") as f:
        json.dump(rows, f, indent=1)
    print("written", os.path.relpath(out, ROOT))


if __name__ == "__main__":
    main()
