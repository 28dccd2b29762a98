"""A punch-through scene: the FEM-DEM model built from a mesh file and the
run parameters (paper Fig. 5, Table 1; docs/model.md §1-3).

- every body (blocks, consolidated layer, indenter) is elastic ice;
- the water line is where the consolidated layer floats freely: its bottom
  sits at draft (ρ_i/ρ_w) t below the water line (docs/model.md §3.4);
- the top of the consolidated layer is held; the indenter top is driven;
- freeze bond points are the nodes of the mesh's bond edges, with strength
  and fracture energy falling linearly with depth below the keel top.
"""
import math

import numpy as np

from .. import engine
from ..files.mesh_file import KIND_BLOCK, KIND_INDENTER, KIND_LAYER, mesh_geometry
from ..geometry.bond_points import find_bond_points

# How far from a phase-1 wall a block node counts as leaning on it (side_walls='held').
WALL_REACH = 0.01


def element_damping_time(params, element_size):
    """Strain-rate damping time [s] giving damping ratio ``damping`` to the
    highest mode an element of size h carries (ω ≈ 2c/h, c the plane-strain
    P-wave speed); the engine damps a mode ω at ratio ω·time/2."""
    c = math.sqrt(params["E"] / (params["rho_i"] * (1.0 - params["nu"] ** 2)))
    omega = 2.0 * c / element_size
    return 2.0 * params["damping"] / omega


class Scene:
    """The model plus what the driver needs to know about it."""

    def __init__(self, mesh, params, threads=0, device="cpu"):
        self.params = params
        self.mesh = mesh
        a = mesh["attrs"]
        geometry = mesh_geometry(mesh)
        self.layer_bottom_y = float(a["layer_bottom_y"])
        self.layer_thickness = geometry["layer_thickness"]
        self.element_size = float(a["element_size"])
        self.keel_top_y = float(a["keel_top_y"])
        self.keel_bottom_y = float(a["keel_bottom_y"])
        self.keel_depth = geometry["keel_depth"]
        # The water line: where this layer floats freely.
        self.y_w = self.layer_bottom_y + params["rho_i"] / params["rho_w"] * self.layer_thickness
        body_kind = np.asarray(mesh["body_kind"])
        self.body_kind = body_kind
        self.indenter_bodies = np.nonzero(body_kind == KIND_INDENTER)[0]
        tri = np.asarray(mesh["triangles"])
        body = np.asarray(mesh["body"])
        self.indenter_nodes = np.unique(tri[body == self.indenter_bodies[0]])
        nodes = np.asarray(mesh["nodes"], dtype=float)
        self.indenter_width = geometry["indenter_width"]
        self.indenter_thickness = geometry["indenter_thickness"]

        self.material = dict(E=params["E"], nu=params["nu"], rho=params["rho_i"],
                             damping=element_damping_time(params, self.element_size),
                             viscosity=params["viscosity"])
        self.threads = threads
        self.device = device   # where the model's steps run (engine.Model device)
        self.bond_points = find_bond_points(
            nodes, tri, body, keel_top_y=self.keel_top_y, keel_depth=self.keel_depth,
            sigma_cr=params["sigma_cr"], tau_cr=params["tau_cr"], G=params["G"],
            bottom_fraction=params["strength_bottom_fraction"],
            exclude_pairs=self._cut_pairs())
        sets = {"layer_top": mesh["layer_top"], "indenter_top": mesh["indenter_top"],
                "indenter": self.indenter_nodes}
        cut = np.asarray(mesh.get("cut_sides", np.zeros(0, np.int32)))
        if cut.size:
            sets["cut_sides"] = cut
        if params["side_walls"] == "held" and not cut.size:
            walls = self._wall_nodes(nodes, tri, body, float(a["domain_width"]))
            if walls.size:
                sets["wall_sides"] = walls
        self.model = engine.Model(nodes, tri, body, materials=self.material, node_sets=sets, device=device)
        self._configure(self.model)
        # bonds hold while the scene settles; the driver switches failure on
        self.model.set_bond_points(self.bond_points, direction=params["force_direction"],
                                   check_failure=False)

    def _configure(self, m):
        p = self.params
        m.set(dt=p["dt"], gravity=True, g=p["g"], buoyancy=True, drag=True,
              drag_model=p["drag_model"], C_d=p["C_d"],
              rho_w=p["rho_w"], y_w=self.y_w, c_w=p["c_w"], penalty=p["penalty"], mu=p["mu"],
              threads=self.threads)

    def restore(self, cp):
        """Replace the model by one continuing checkpoint ``cp`` (engine.Model.checkpoint)."""
        m = engine.Model.from_checkpoint(cp, self.material, device=self.device)
        self._configure(m)
        m.restore_checkpoint(cp)
        self.model = m
        return m

    def _wall_nodes(self, nodes, tri, body, domain_width):
        """The block nodes where phase 1's walls stood: within WALL_REACH of
        |x| = W/2 (a block that leaned on a wall has a corner or a face there,
        within the overlap of phase 1's contacts, a few mm)."""
        block_nodes = np.unique(tri[self.body_kind[body] == KIND_BLOCK])
        near = np.abs(np.abs(nodes[block_nodes, 0]) - 0.5 * domain_width) < WALL_REACH
        return block_nodes[near].astype(np.int32)

    def hold_boundaries(self, m):
        """The scene's held nodes: the consolidated layer's top, and the faces
        a cropped scene's crop cut, held in x as the rest of the pile held them
        (a roller: they slide up and down); with side_walls='held', the block
        nodes where an uncropped scene's phase-1 walls stood, likewise."""
        m.fix("layer_top")
        for ends in ("cut_sides", "wall_sides"):
            if ends in m.node_sets:
                m.fix(ends, x=True, y=False)

    def _cut_pairs(self):
        """Indenter and consolidated layer are cut apart, never frozen together."""
        ind = self.indenter_bodies[0]
        return [(int(ind), int(b)) for b in np.nonzero(self.body_kind == KIND_LAYER)[0]]

    # --- what the driver measures --------------------------------------
    def indenter_top_y(self):
        return float(np.mean(self.model.y[self.model.node_sets["indenter_top"]]))

    def indenter_net_buoyancy(self):
        """Buoyancy minus weight of the indenter plate [N/m, up positive], from
        its current draft: subtracted from the push so that F is the rubble's
        resistance alone (docs/model.md §1)."""
        p = self.params
        bottom = self.indenter_top_y() - self.indenter_thickness
        submerged = min(max(self.y_w - bottom, 0.0), self.indenter_thickness)
        w = self.indenter_width
        return p["g"] * w * (p["rho_w"] * submerged - p["rho_i"] * self.indenter_thickness)

    def indenter_force(self):
        """F [N/m]: the push the indenter boundary exerts downward, minus the
        indenter's own net buoyancy: the rubble's resistance."""
        push = -float(self.model.reaction("indenter_top")[1])
        return push - self.indenter_net_buoyancy()
