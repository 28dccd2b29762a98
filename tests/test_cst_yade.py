"""The engine imports and runs inside YADE (BRIEF.md: YADE hosts the workflow)."""
import os
import subprocess
import textwrap


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_engine_runs_inside_yade(tmp_path):
    script = tmp_path / "fdem_in_yade.py"
    script.write_text(textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {ROOT!r})
        import numpy as np
        from icerubble import fdem
        nodes, tri = fdem.rectangle_mesh(4, 2, 0.25)
        m = fdem.Model(nodes, tri, np.zeros(len(tri), int), dict(E=1e9, nu=0.3, rho=900.0))
        m.set(dt=1e-5)
        m.step(10)
        # free fall from rest: v = -g t for the central difference (v starts at t = -dt/2)
        print("FDEM_VY", m.velocities[:, 1].mean() / (-9.81 * m.time))
    """))
    out = subprocess.run(["yade", "-n", "-x", str(script)], capture_output=True, text=True,
                         timeout=120, cwd=str(tmp_path))
    line = [l for l in out.stdout.splitlines() if l.startswith("FDEM_VY")]
    assert line, out.stdout + out.stderr
    assert abs(float(line[0].split()[1]) - 1.0) < 1e-9  # round-off of m g / m over 10 steps
