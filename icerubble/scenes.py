"""Named scenes: pile, mesh and numerical settings that go together.

``paper`` is the paper's set-up (Table 1): a 50 m wide, ~4 m deep keel, an
element size giving ~150,000 dof, the paper's penalty and time step.
``small`` and ``demo`` are a 10 m wide, ~1.8 m deep keel on a coarser mesh
that runs in minutes on a workstation; to afford a 5x larger time step they
use a 10x softer contact penalty (2e10 Pa: contact overlaps stay below a
micrometre at these loads). Everything else is Table 1.
"""
SCENES = {
    "paper": dict(
        pile=dict(domain_width=50.0, keel_depth=4.0),
        element_size=0.055,
        params=dict(dt=1e-6, penalty=2e11, target_travel=0.3),
    ),
    "small": dict(
        pile=dict(domain_width=10.0, keel_depth=1.8),
        element_size=0.15,
        params=dict(dt=5e-6, penalty=2e10, target_travel=0.03),
    ),
    "demo": dict(
        pile=dict(domain_width=10.0, keel_depth=1.8),
        element_size=0.15,
        params=dict(dt=5e-6, penalty=2e10, target_travel=0.03),
    ),
}


def scene(name):
    if name not in SCENES:
        raise ValueError(f"scene={name!r} is unknown: valid values are {', '.join(sorted(SCENES))}")
    return SCENES[name]
