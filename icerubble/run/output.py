"""What a punch-through run writes (docs/results_format.md): the snapshots
of the loading (in the result, and as ParaView VTU pieces beside it), the
bond events with their travel, and the one self-describing HDF5 result with
the PVD collection of the pieces, written once the run is complete.
``Output(run)`` does it for a PunchThrough ``run`` (run/punch_through_run.py).
"""
import json
import os

import numpy as np

from ..files.vtu import write_pvd, write_vtu
from .split_traction import point_split_traction


class Output:
    def __init__(self, run):
        self.driver = run

    def snapshot(self, t_rel, y_I):
        r = self.driver
        m = r.model
        r.recorder.snapshot(t_rel, y_I, m.positions, m.triangles)
        if r.options.vtu:
            base = os.path.basename(r.out_path)[:-3]
            d = r.out_path[:-3] + "_fields"
            os.makedirs(d, exist_ok=True)
            name = f"{base}_{len(r.state.vtu_entries):04d}.vtu"
            u = m.positions - m.reference_positions
            s = m.stress
            write_vtu(os.path.join(d, name), m.positions, m.triangles,
                      point_data={"u_total": u},
                      cell_data={"body": m.body, "body_kind": r.scene.body_kind[m.body].astype(np.int8),
                                 "u_since_loading": r.recorder.snapshots[-1][2],
                                 "stress": np.asarray(s)})
            r.state.vtu_entries.append((y_I, name))
            # the collection is written once the result is (write()): a
            # killed run leaves .vtu pieces but no .pvd that looks complete

    def bond_events(self):
        """The engine's bond event log with times from the start of loading
        and the indenter travel at each event (interpolated in the F record)."""
        r = self.driver
        ev = r.model.bonds.events()
        fr = np.array(r.recorder.force_rows, dtype=float).reshape(-1, 4)
        out = {}
        for kind in ("split", "fail"):
            t = np.asarray(ev[f"t_{kind}"], dtype=float) - r.state.t_load
            y = np.full_like(t, np.nan)
            # t < 0: during the settle (settle_bonds='checked'), part of the
            # initial state, at no travel: y_I stays NaN, t says when
            ok = np.isfinite(t) & (t >= 0.0)
            if len(fr) >= 2:
                y[ok] = np.interp(t[ok], fr[:, 0], fr[:, 1])
            out[f"t_{kind}"], out[f"y_I_{kind}"] = t, y
        out["delta_n_fail"] = ev["delta_n_fail"]
        out["delta_t_fail"] = ev["delta_t_fail"]
        out["mode"] = ev["mode"]
        bond_mu = r.model.bond_params["mu"]   # None: eq 6 takes the contact friction
        out["split_tn"], out["split_tt"] = point_split_traction(
            ev["pair_point"], ev["pair_split_tn"], ev["pair_split_tt"], r.recorder.bp.sigma_cr,
            r.recorder.bp.tau_cr, r.model.params["mu"] if bond_mu is None else bond_mu)
        return out

    def write(self):
        r = self.driver
        if r.options.mass_scaling_dt is not None:
            # the contact reach guard may have raised nodes mid-run (engine masses.cpp)
            st = r.model.stable_time_step()
            r.recorder.meta.update(added_mass_fraction_end=st["added_mass_fraction"],
                                   scaled_nodes_end=st["scaled_nodes"])
        r.recorder.meta.update(F_at_rest=r.state.F_at_rest, settle_time=r.state.settle_time,
                               settle_max_speed=r.state.settle_max_speed,
                               settle_max_block_move=r.state.settle_max_block_move,
                               settle_splits=int(r.state.settle_splits),
                               load_steps=int(r.state.load_steps), n_triangles=int(r.model.n_triangles),
                               load_element_steps=int(r.state.load_element_steps),
                               sleep=json.dumps(r.options.sleep))
        # a run loaded from another run's rest state (run_from_rest) did not
        # settle at its own settle step; one from a shared rest state did (it is in the key)
        if r.options.settle_mass_scaling_dt is not None and (
                r.rest_state is None or r.recorder.meta.get("rest_state_shared")):
            r.recorder.meta.update(settle_mass_scaling_dt=r.options.settle_mass_scaling_dt)
        r.recorder.bond_events(self.bond_events())
        r.recorder.write(r.out_path)
        if r.options.vtu and r.state.vtu_entries:
            base = os.path.basename(r.out_path)[:-3]
            write_pvd(os.path.join(r.out_path[:-3] + "_fields", base + ".pvd"), r.state.vtu_entries)
