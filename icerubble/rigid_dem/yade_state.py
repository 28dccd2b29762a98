"""A rigid ridge (scene.rigid_scene, or a FEM-DEM snapshot: snapshot.fem_dem_state)
put into the current YADE scene as RigidPunchThrough.build puts one
(docs/model.md §6): the same ridge seen two ways, taken up where the FEM-DEM
had it. Only inside YADE (`yade -n -x`, e.g. yade_scripts/load_state.py).

    sc = fem_dem_state("runs/x.h5", y_I=0.02)
    O.reset()
    st = load_into_yade(sc)            # bodies, step, coupling, engines
    O.run(1000, True)                  # st.coupling, st.ids, st.hull_added_area, ...

Bodies as build() makes them: each polygon's convex hull (YADE polyhedra are
convex; the largest relative area gained is kept), inset by INSET, a 1 m
prism; the layer fixed, the indenter moving only up and down, the blocks in
the plane. The bonds are anchored where the bodies are placed: every kept pair
starts intact, at zero opening (a FEM-DEM pair past its peak starts afresh:
sc["bond_split"] says which). The laws are as while loading: no damping,
drag and bond failure on, the indenter free in the water (a driver that
drives it sets coupling.dry and its velocity, as build's run does).

The bodies, step and bonds are those of prisms.py; RigidPunchThrough.build
makes its scene with load_into_yade too.
"""
import builtins
from dataclasses import dataclass

import numpy as np
from yade.wrapper import (O, PolyhedraMat, ForceResetter, InsertionSortCollider, Bo1_Polyhedra_Aabb,
                          InteractionLoop, Ig2_Polyhedra_Polyhedra_PolyhedraGeom,
                          Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys,
                          Law2_PolyhedraGeom_PolyhedraPhys_Volumetric, NewtonIntegrator, PyRunner)

from .prisms import bond_arrays, place_bodies, rigid_step
from .scene import KIND_BLOCK, KIND_LAYER
from .yade_coupling import Coupling


@dataclass
class LoadedState:
    ids: np.ndarray          # YADE id of every body of the scene dict, in its order
    blocks: np.ndarray       # YADE ids of the blocks
    indenter: int            # YADE id of the indenter
    layer: np.ndarray        # YADE ids of the layer pieces (fixed)
    polygons: list           # each body's outline as placed (hull, inset) [m]
    hull_gain: np.ndarray    # per body: hull area / outline area - 1
    hull_added_area: float   # the largest of them (what a rigid result records)
    dt: float                # [s] the step set in O.dt
    coupling: Coupling
    newton: NewtonIntegrator


def load_into_yade(sc, damping=0.0, failure=True, drag=True, step_command="_loaded_state.coupling()"):
    """`sc` into the current YADE scene (call O.reset() first for a scene of
    its own): material, bodies, O.dt, the coupling (friction, water, bonds
    anchored as placed) and O.engines with it. `damping`: Cundall's, as
    NewtonIntegrator's; `failure`, `drag`: the bonds' and the water's switches;
    `step_command`: what the PyRunner runs each step (default: the coupling,
    as `_loaded_state`, the LoadedState returned). Returns a LoadedState."""
    p = sc["params"]
    mat = PolyhedraMat(density=p["rho_i"], young=p["E"], poisson=p["nu"], frictionAngle=0.0)
    O.materials.append(mat)
    ids, polys, gain = place_bodies(mat, sc)
    dt, t_min = rigid_step(sc, ids, polys)
    O.dt = dt
    kind = sc["body_kind"]
    blocks, indenter = ids[kind == KIND_BLOCK], int(ids[sc["indenter"]])
    coupling = Coupling(np.append(blocks, indenter), mu=p["mu"], k_t=0.5 * p["E"] * t_min, dt=dt,
                        water=dict(params=p, y_w=sc["y_w"]), bonds=bond_arrays(sc, ids))
    coupling.bonds.failure = failure
    coupling.water.drag = drag
    newton = NewtonIntegrator(damping=damping, gravity=(0.0, -p["g"], 0.0))
    st = LoadedState(ids=ids, blocks=blocks, indenter=indenter, layer=ids[kind == KIND_LAYER], polygons=polys,
                     hull_gain=gain, hull_added_area=float(gain.max()), dt=dt, coupling=coupling, newton=newton)
    builtins._loaded_state = st   # PyRunner commands run in YADE's __main__ namespace
    O.engines = [ForceResetter(),
                 InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=0.05 * t_min),
                 InteractionLoop([Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
                                 [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
                                 [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()]),
                 PyRunner(iterPeriod=1, command=step_command),
                 newton]
    return st
