"""The discrete-only comparison model (docs/model.md §6): the same ridge as
rigid blocks in YADE, with the project's water law, friction and freeze bonds.

- `water`: buoyancy and drag on rigid polygon blocks (engine, rigid/rigid_water.hpp).
- friction with stick, one history per contact: `icerubble._engine.RigidFriction`
  (engine, rigid/rigid_friction.hpp).
- freeze bonds, initially elastic: `icerubble._engine.RigidBonds` (engine, rigid/rigid_bonds.hpp).
- `scene`: a FEM-DEM mesh as rigid bodies (its outlines) and its bond pairs (the same points).
- `yade_coupling`: the per-step exchange with a YADE scene of prisms (inside YADE only).
- `prisms`: a block as a YADE prism (convex, inset, turning about z at its own moment),
  and the bodies, step and bond arrays of a rigid ridge (inside YADE only).
- `punch_through`: the rigid punch-through driver, the FEM-DEM run's phases and result file.
- `energy`: the rigid run's energy ledger, paid out as YADE's leapfrog integrates.
- `snapshot`: a FEM-DEM result at one of its snapshots as the same description
  (the deformed bodies, the bond pairs not failed by then).
- `yade_state`: such a description put into a YADE scene as prisms with the coupling (inside YADE only).
"""
