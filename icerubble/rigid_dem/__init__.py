"""The discrete-only comparison model (docs/model.md §6): the same ridge as
rigid blocks in YADE, with the project's water law, friction and freeze bonds.

- `water`: buoyancy and drag on rigid polygon blocks (engine, rigid/rigid_water.hpp).
- friction with stick, one history per contact: `icerubble._engine.RigidFriction`
  (engine, rigid/rigid_friction.hpp).
- freeze bonds, initially elastic: `icerubble._engine.RigidBonds` (engine, rigid/rigid_bonds.hpp).
- `scene`: a FEM-DEM mesh as rigid bodies (its outlines) and its bond pairs (the same points).
- `yade_coupling`: the per-step exchange with a YADE scene of prisms (inside YADE only).
"""
