"""The engine imports and runs inside YADE (YADE hosts the workflow): the
installed package, from any folder, no path set by the script."""
import subprocess
import textwrap


def test_engine_runs_inside_yade(tmp_path):
    script = tmp_path / "fdem_in_yade.py"
    script.write_text(textwrap.dedent("""
        import numpy as np
        from icerubble import engine
        nodes, tri = engine.rectangle_mesh(4, 2, 0.25)
        m = engine.Model(nodes, tri, np.zeros(len(tri), int), dict(E=1e9, nu=0.3, rho=900.0))
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
