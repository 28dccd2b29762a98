"""The FEM-DEM engine: deformable blocks (CST), potential contact with friction,
freeze bonds, water and gravity, explicit time stepping (docs/model.md §3).

The loops run in the compiled module; this package is its Python API
(docs/engine_api.md)::

    from icerubble import engine
    m = engine.Model(nodes, triangles, body, materials=dict(E=2e9, nu=0.3, rho=920.0))
"""
from .model import (DEVICES, DRAG_MODELS, MATERIAL_DEFAULTS, MATERIAL_KEYS, PARAMETERS, BondsView,
                    InstabilityError, Model, check_device, ramp_velocity, rectangle_mesh)

__all__ = ["Model", "BondsView", "InstabilityError", "rectangle_mesh", "ramp_velocity", "PARAMETERS",
           "MATERIAL_KEYS", "MATERIAL_DEFAULTS", "DRAG_MODELS", "DEVICES", "check_device"]
