"""What a punch-through run records (docs/model.md §4), written as docs/results_format.md
(its reader: results.py).

The recorder only holds arrays and writes them; the driver decides when to
sample. Its state (everything recorded so far) goes into checkpoints, so a
resumed run writes the same file an uninterrupted one would.
"""
import numpy as np

from .. import parameters as P
from .. import machine
from .h5io import AtomicH5, set_attrs, write_dataset

RESULT_FORMAT = "icerubble-run"

ENERGY_TERMS = ("kinetic", "elastic", "contact", "friction", "damping", "drag", "cohesive",
                "work_gravity", "work_buoyancy", "work_boundary", "residual")

BOND_FIELDS = {  # name: (units, dtype, fill)
    "t_split": ("s", float, np.nan), "y_I_split": ("m", float, np.nan),
    "t_fail": ("s", float, np.nan), "y_I_fail": ("m", float, np.nan),
    "delta_n_fail": ("m", float, np.nan), "delta_t_fail": ("m", float, np.nan),
    "mode": ("-", np.int8, 0),
    # traction at the split (icerubble/run/split_traction.py): which side of eq 6 it began on
    "split_tn": ("Pa", float, np.nan), "split_tt": ("Pa", float, np.nan),
}


def snapshot_travels(target_travel):
    """Indenter travels [m] of the u snapshots: 1, 5, 10, 20, 30, ... mm up to the target."""
    mm = [1.0, 5.0] + list(np.arange(10.0, target_travel * 1e3 + 1e-9, 10.0))
    return [v * 1e-3 for v in mm if v * 1e-3 <= target_travel + 1e-12]


class RunRecorder:
    def __init__(self, params, mesh, bond_points, pile_attrs, meta):
        """params: validated parameter dict; mesh: dict with nodes, triangles,
        body, body_kind; bond_points: icerubble.geometry.bond_points.BondPoints;
        pile_attrs: porosity etc.; meta: ridge, seed, model."""
        self.params = dict(params)
        self.mesh = {k: np.asarray(v) for k, v in mesh.items()}
        self.bp = bond_points
        self.pile_attrs = dict(pile_attrs)
        self.meta = dict(meta)
        nodes, tri = self.mesh["nodes"], self.mesh["triangles"]
        p = nodes[tri]
        self.area0 = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                            - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
        self.centroid0 = p.mean(axis=1)
        self.force_rows = []       # (t, y_I, F, F_instant)
        self.energy_rows = []      # (t, *ENERGY_TERMS)
        self.snapshots = []        # (t, y_I, u_elem, u_node)
        self.pending_snaps = snapshot_travels(self.params["target_travel"])
        self.bonds = {k: np.full(len(bond_points), fill, dtype=dt) for k, (_, dt, fill) in BOND_FIELDS.items()}
        self.reference_nodes = nodes[:, :2].copy()   # u is measured from the settled state

    def set_reference(self, node_positions):
        """Displacements are measured from the rest state reached before the indenter moves."""
        self.reference_nodes = np.array(node_positions[: len(self.mesh["nodes"])], dtype=float)
        p = self.reference_nodes[self.mesh["triangles"]]
        self.centroid0 = p.mean(axis=1)

    def force(self, t, y_I, F, F_instant=None):
        """F: the indenter force over the interval since the last sample (its mean
        with respect to travel); F_instant: its value at this step (default F)."""
        self.force_rows.append((t, y_I, F, F if F_instant is None else F_instant))

    def energy(self, t, terms):
        self.energy_rows.append((t,) + tuple(float(terms.get(k, np.nan)) for k in ENERGY_TERMS))

    def wants_snapshot(self, y_I):
        return bool(self.pending_snaps) and y_I >= self.pending_snaps[0] - 1e-12

    def snapshot(self, t, y_I, node_positions, triangles_now):
        """node_positions: current positions of all nodes (split nodes appended
        after the original ones); triangles_now: current connectivity."""
        x = np.asarray(node_positions, dtype=float)
        cent = x[np.asarray(triangles_now)].mean(axis=1)
        u_elem = cent - self.centroid0
        u_node = x[: len(self.reference_nodes)] - self.reference_nodes
        self.snapshots.append((t, y_I, u_elem, u_node))
        while self.pending_snaps and y_I >= self.pending_snaps[0] - 1e-12:
            self.pending_snaps.pop(0)

    def bond_events(self, events):
        """events: dict of arrays named as BOND_FIELDS, one entry per bond point."""
        for k in BOND_FIELDS:
            if k in events:
                self.bonds[k][:] = events[k]

    # --- checkpoints -------------------------------------------------------
    def state(self):
        return dict(force_rows=list(self.force_rows), energy_rows=list(self.energy_rows),
                    snapshots=list(self.snapshots), pending_snaps=list(self.pending_snaps),
                    bonds={k: v.copy() for k, v in self.bonds.items()},
                    reference_nodes=self.reference_nodes.copy(), centroid0=self.centroid0.copy())

    def restore(self, s):
        for k, v in s.items():
            setattr(self, k, v)
        # a checkpoint from before a field was recorded: the field starts at its fill
        for k, (_, dt, fill) in BOND_FIELDS.items():
            if k not in self.bonds:
                self.bonds[k] = np.full(len(self.bp), fill, dtype=dt)

    # --- output ------------------------------------------------------------
    def write(self, path):
        units = P.units()
        with AtomicH5(path, RESULT_FORMAT) as f:
            set_attrs(f, {k: self.meta[k] for k in self.meta})
            # where the bits of this result could differ (docs/reproducibility.md)
            f.attrs["engine_build"] = machine.engine_build()
            f.attrs["processor"] = machine.processor()
            g = f.create_group("parameters")
            set_attrs(g, self.params)
            for k, v in self.params.items():
                if k in units:
                    g.attrs[k + "_units"] = units[k]
            set_attrs(f.create_group("pile"), self.pile_attrs)
            m = f.create_group("mesh")
            write_dataset(m, "nodes", self.mesh["nodes"][:, :2], "m")
            write_dataset(m, "triangles", self.mesh["triangles"].astype(np.int32), "-")
            write_dataset(m, "body", self.mesh["body"].astype(np.int32), "-")
            write_dataset(m, "body_kind", self.mesh["body_kind"].astype(np.int8), "-",
                          codes="0 block, 1 consolidated layer, 2 indenter")
            write_dataset(m, "area", self.area0, "m^2")
            write_dataset(m, "centroid", self.centroid0, "m")
            fr = np.array(self.force_rows, dtype=float).reshape(-1, 4)
            fg = f.create_group("force")
            write_dataset(fg, "t", fr[:, 0], "s")
            write_dataset(fg, "y_I", fr[:, 1], "m", direction="indenter travel, down positive")
            write_dataset(fg, "F", fr[:, 2], "N/m",
                          meaning="rubble resistance on the indenter, indenter buoyancy subtracted; "
                                  "mean over the travel since the previous sample (work / travel)")
            write_dataset(fg, "F_instant", fr[:, 3], "N/m",
                          meaning="the same force at the sample's time step (no averaging)")
            sg = f.create_group("snapshots")
            for i, (t, y, ue, un) in enumerate(self.snapshots):
                s = sg.create_group(f"{i:04d}")
                s.attrs["t"], s.attrs["y_I"] = t, y
                write_dataset(s, "u_elem", ue, "m")
                write_dataset(s, "u_node", un, "m")
            bg = f.create_group("bonds")
            bp = self.bp
            write_dataset(bg, "position", bp.position, "m")
            write_dataset(bg, "depth", bp.depth, "m")
            write_dataset(bg, "bodies", np.where(bp.n_bodies[:, None] > 2, -1, bp.bodies).astype(np.int32), "-")
            write_dataset(bg, "length", bp.length, "m")
            write_dataset(bg, "sigma_cr", bp.sigma_cr, "Pa")
            write_dataset(bg, "tau_cr", bp.tau_cr, "Pa")
            write_dataset(bg, "G", bp.G, "J/m^2")
            for k, (u, _, _) in BOND_FIELDS.items():
                write_dataset(bg, k, self.bonds[k], u)
            bg["mode"].attrs["codes"] = "0 intact or cohesive, 1 tensile, 2 shear"
            er = np.array(self.energy_rows, dtype=float).reshape(-1, 1 + len(ENERGY_TERMS))
            eg = f.create_group("energy")
            write_dataset(eg, "t", er[:, 0], "s")
            for i, k in enumerate(ENERGY_TERMS):
                write_dataset(eg, k, er[:, 1 + i], "J/m")


def write_recorder_state(group, s):
    """A recorder's state (RunRecorder.state()) into an HDF5 group: what a
    checkpoint of either model keeps of its record so far."""
    group.create_dataset("force_rows", data=np.array(s["force_rows"], float).reshape(-1, 4))
    group.create_dataset("energy_rows", data=np.array(s["energy_rows"], float).reshape(-1, 1 + len(ENERGY_TERMS)))
    group.create_dataset("pending_snaps", data=np.array(s["pending_snaps"], float))
    group.create_dataset("reference_nodes", data=s["reference_nodes"])
    group.create_dataset("centroid0", data=s["centroid0"])
    b = group.create_group("bonds")
    for k, v in s["bonds"].items():
        b.create_dataset(k, data=v)
    sn = group.create_group("snapshots")
    for i, (t, y, ue, un) in enumerate(s["snapshots"]):
        g = sn.create_group(f"{i:04d}")
        g.attrs["t"], g.attrs["y_I"] = t, y
        g.create_dataset("u_elem", data=ue)
        g.create_dataset("u_node", data=un)


def read_recorder_state(group):
    """Inverse of write_recorder_state: a state RunRecorder.restore takes."""
    r = group
    return dict(force_rows=[tuple(row) for row in r["force_rows"][...]],
                energy_rows=[tuple(row) for row in r["energy_rows"][...]],
                pending_snaps=list(r["pending_snaps"][...]),
                reference_nodes=r["reference_nodes"][...], centroid0=r["centroid0"][...],
                bonds={k: r["bonds"][k][...] for k in r["bonds"]},
                snapshots=[(r["snapshots"][k].attrs["t"], r["snapshots"][k].attrs["y_I"],
                            r["snapshots"][k]["u_elem"][...], r["snapshots"][k]["u_node"][...])
                           for k in sorted(r["snapshots"])])
