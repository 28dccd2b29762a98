"""Timings of phase 1 (YADE pile) and of the gmsh meshing; prints figures, asserts nothing.

    /usr/bin/python3 bench/pile_mesh.py                 demo pile (~40 blocks, 10 m)
    /usr/bin/python3 bench/pile_mesh.py --full          also the 665-block, 50 m pile (~5-15 min)
    /usr/bin/python3 bench/pile_mesh.py --pile P.h5     only mesh an existing pile
Machines are shared and noisy: treat the times as +-30 %.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

from icerubble.files import pile_file
from icerubble.geometry import meshing

DOF_TARGET = 150_000  # paper Table 1 (2 dof per node)


def run_phase1(tmp, name, threads, **params):
    out = os.path.join(tmp, name + ".h5")
    params = dict(params, out=f"'{out}'")
    table = os.path.join(tmp, name + ".table")
    with open(table, "w") as f:
        f.write("description " + " ".join(params) + "\n")
        f.write(name + " " + " ".join(str(v) for v in params.values()) + "\n")
    env = dict(os.environ, YADE_BATCH=f"{table}:2")
    t0 = time.perf_counter()
    proc = subprocess.run(["yade", f"-j{threads}", "-n", "-x",
                           os.path.join(ROOT, "yade_scripts", "make_pile.py")],
                          cwd=tmp, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"phase 1 failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    p = pile_file.read_pile(out)
    m = p["meta"]
    print(f"phase 1 {name}: {m['n_blocks']} blocks, {threads} thread(s): {wall:.1f} s wall "
          f"(YADE loop {m['wall_time']:.1f} s), {m['steps']} steps of {m['dt']:.3g} s, "
          f"{m['settle_time']:.2f} s simulated, settled={m['settled']}, "
          f"KE/block {m['ke_per_block']:.2e} J/m, keel {m['keel_top_y'] - m['keel_bottom_y']:.2f} m, "
          f"porosity (soft-contact pile) {m['porosity']:.3f}", flush=True)
    return out


def mesh_once(path, h):
    p = pile_file.read_pile(path)
    t0 = time.perf_counter()
    m = meshing.build_mesh(p, element_size=h)
    wall = time.perf_counter() - t0
    q, t = m["quality"], m["times"]
    c = m["contacts"]
    print(f"  mesh h={h:.3f} m: {wall:.1f} s (resolve {t['resolve']:.1f}, fragment {t['fragment']:.1f}, "
          f"mesh {t['mesh']:.1f}); {len(m['nodes'])} nodes ({2 * len(m['nodes'])} dof), "
          f"{len(m['triangles'])} triangles, {len(m['bond_edges'])} bond edges, "
          f"{int(c['bonded'].sum())}/{len(c['bonded'])} contacts bonded; min angle "
          f"{q['min_angle_deg']:.1f} deg, min edge {q['min_edge'] * 1e3:.2f} mm, "
          f"porosity {m['porosity']:.3f}", flush=True)
    return m


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--full", action="store_true", help="also the 665-block paper-size pile")
    ap.add_argument("--pile", help="mesh this pile file only (no phase 1)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        if a.pile:
            piles = [(a.pile, True)]
        else:
            piles = [(run_phase1(tmp, "demo", 1), False)]
            if a.full:
                piles.append((run_phase1(tmp, "paper665", 2, n_blocks=665, domain_width=50.0,
                                         E_settle=1e7, max_time=200.0), True))
        for path, search in piles:
            print(f"meshing {os.path.basename(path)}:")
            m = mesh_once(path, 0.1)
            if search:
                # dof ~ 1/h^2 away from small features: two secant steps to ~150,000 dof
                h = 0.1
                for _ in range(2):
                    h = round(h * (2 * len(m["nodes"]) / DOF_TARGET) ** 0.5, 4)
                    m = mesh_once(path, h)


if __name__ == "__main__":
    main()
