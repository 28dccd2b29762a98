"""Named scenes: pile, mesh and the numerical settings that go with them.

Only the settings are here; what they cost and change is measured in
bench/README.md, the piles' porosity and keel depth in docs/pile_and_mesh.md.

``paper`` is the paper's set-up (Table 1): a 50 m wide, 4 m deep keel as loose
as the paper's, the paper's element size class and Table 1's penalty; its
piles form as the paper's (PAPER_PILE below). At that penalty the few tiny
elements of a real pile's mesh bring the stable step far below the paper's
1 us, so the paper scene scales the inertial mass of the nodes that limit it
(weight stays physical); see NUMERICS below and docs/speed_and_accuracy.md.
``deep`` is the central 20 m of the paper scene's ridges on 0.15 m elements,
with the paper's penalty and strengths: the paper's keel at a workstation's
cost (docs/study_paper_depth.md).
``small`` and ``demo`` are a 10 m wide, 1.8 m deep keel on a coarser mesh
(0.15 m) that runs in minutes on a workstation; ``wide`` is the same at 30 m
(a far field). To afford a larger time step they use a 40x softer contact
penalty than Table 1's (5e9 Pa: contact overlaps stay of the order of
micrometres at these loads); the demo and wide scenes also ramp the indenter
up in 0.5 s instead of Table 1's 2 s. Where the pile leaves a 2-4 mm element
at a block junction (the block viscosity makes such an element's limit fall
as its size squared), they scale the masses of those few nodes to a 3e-6 s
step (the added mass is recorded in the result).
``tiny`` (8 blocks, 2 mm of travel, a 0.1 s ramp: seconds) checks that a
set-up runs.
Everything else is Table 1. Deviations are recorded in every result file's
/parameters.

The coarse scenes' piles are settled in phase 1 at PILE_FRICTION = 0.05, the
lowest friction coefficient of the paper's study, from a compact start tilted
at most 30 deg: at rest within the 0.05 friction cone, they are at rest within
the 0.3 cone too, and dense. The paper scene's piles form at 0.3 from random
orientations, as loose as the paper's, and are then held at 0.05 with their
face contacts frozen (where the mesh bonds them) until the blocks held by
friction alone have slid to a new rest: at rest at every mu of the study
(docs/pile_and_mesh.md). The pile and mesh file names carry the friction the
pile formed at (icerubble/run/scene_cache.py).
"""
# Friction of phase 1 (yade_scripts/make_pile.py mu_settle) of the coarse
# scenes' dense piles: the lowest mu of the study.
PILE_FRICTION = 0.05

# The paper's phase 1 (section 2.4): blocks "released under water with random
# orientations and velocities" (tilt uniform in +-90 deg), rising and settling
# with the friction of ice on ice (Table 1's rougher value, 0.3), their number
# filling Table 1's keel (h ~ 4 m at porosity ~0.25) in the 50 m domain.
# Measured: porosity (void/total) and keel depth in docs/pile_and_mesh.md.
# Then the hold stage: freeze bonds form where blocks meet on a face, and every
# other contact slides at the study's lowest mu until the pile is at rest there
# too (make_pile.py mu_hold), so the pile is at rest at every mu of the study.
PAPER_PILE = dict(domain_width=50.0, keel_depth=4.0, porosity_guess=0.25, mu_settle=0.3,
                  max_tilt=90.0, mu_hold=PILE_FRICTION)

SCENES = {
    "paper": dict(
        pile=PAPER_PILE,
        element_size=0.085,
        params=dict(penalty=2e11, target_travel=0.3),
    ),
    "small": dict(
        pile=dict(domain_width=10.0, keel_depth=1.8, mu_settle=PILE_FRICTION),
        element_size=0.15,
        params=dict(penalty=5e9, target_travel=0.03),
    ),
    # The paper's keel depth, penalty and strengths in a domain a workstation
    # can study: the central 20 m of the paper scene's ridge N (its pile cut at
    # x = +-10 m, as phase 1's walls cut it), so the paper scene itself is the
    # reference for what the narrower domain and coarser mesh cost
    # (docs/study_paper_depth.md).
    "deep": dict(
        pile_of="paper", domain_width=20.0,
        element_size=0.15,
        params=dict(penalty=2e11, target_travel=0.02),
    ),
    # a 30 m keel at the demo's resolution: wide enough for a far field that
    # barely moves (where the sleeping far field pays; bench/runtime_vs_error.py)
    "wide": dict(
        pile=dict(domain_width=30.0, keel_depth=1.8, mu_settle=PILE_FRICTION),
        element_size=0.15,
        params=dict(penalty=5e9, target_travel=0.03, ramp_time=0.5),
    ),
    "demo": dict(
        pile=dict(domain_width=10.0, keel_depth=1.8, mu_settle=PILE_FRICTION),
        element_size=0.15,
        params=dict(penalty=5e9, target_travel=0.03, ramp_time=0.5),
    ),
    # 8 blocks under a 6 m layer, 2 mm of travel: a whole run in seconds, to
    # check that a set-up works (a table, a cluster, an install) before the
    # real study; not a ridge (too few blocks for a keel's mechanics: at
    # mu = 0.05 ridge 1's blocks do not come to rest, 0.2 m of sliding in the
    # 5 s settle, and the run stops saying so; at Table 1's mu = 0.3 they do)
    "tiny": dict(
        pile=dict(domain_width=6.0, keel_depth=0.6, mu_settle=PILE_FRICTION),
        element_size=0.2,
        params=dict(penalty=5e9, target_travel=0.002, ramp_time=0.1),
    ),
}


# Numerical presets of each scene (a table's `numerics` column): how much
# accuracy to trade for speed. "paper" is the scene's faithful setting (the
# default); "balanced" bounds the contact step locally (contact_reach: a
# larger step, and on the paper scene a larger mass-scaling target for the
# same added mass); "fast" also runs at 0.95 of the stable step (at 1.0 the
# step recomputed after a bond split could differ from it in the last digits).
# What each costs in accuracy is measured by bench/runtime_vs_error.py
# (bench/README.md; docs/speed_and_accuracy.md).
# The sleeping far field (RunOptions sleep) is in no preset: on the 30 m wide
# keel it saves a few per cent of the element work and moves F^m by more than
# the step's scatter (bench/sleeping.py): once the first bonds fail, the whole
# keel rings (docs/model.md §3.5), so no body stays at rest for long.
NUMERICS = {
    "paper": {
        "paper": dict(dt_fraction=0.8, mass_scaling_dt=2e-7),
        # a 3 mm reach: nodes are bounded against what they can meet in the next
        # 3 mm (the reach guard raises a node's mass when a block comes closer),
        # which affords a larger mass-scaling target for little added mass; they
        # settle at twice their loading step (dynamic relaxation with more
        # inertial mass on the boundary nodes: the settle's steps halve;
        # docs/model.md §3 "A larger step while settling"; the added masses:
        # bench/README.md, paper_cost.json)
        "balanced": dict(dt_fraction=0.8, mass_scaling_dt=1e-6, contact_reach=0.003,
                         settle_mass_scaling_dt=2e-6),
        "fast": dict(dt_fraction=0.95, mass_scaling_dt=1.2e-6, contact_reach=0.003,
                     settle_mass_scaling_dt=2.4e-6),
    },
}
# the deep scene has the paper scene's penalty: the same numerics
NUMERICS["deep"] = {k: dict(v) for k, v in NUMERICS["paper"].items()}
for _name in ("small", "wide", "demo", "tiny"):
    NUMERICS[_name] = {
        "paper": dict(dt_fraction=0.8, mass_scaling_dt=3e-6),
        # settling at 4x the step: a fraction of the settle's steps, the same rest
        # (tests/run/test_settle_mu.py)
        "balanced": dict(dt_fraction=0.8, mass_scaling_dt=3e-6, contact_reach=0.1, settle_mass_scaling_dt=1.2e-5),
        "fast": dict(dt_fraction=0.95, mass_scaling_dt=3e-6, contact_reach=0.1, settle_mass_scaling_dt=1.2e-5),
    }
DEFAULT_NUMERICS = "paper"


def numerics(scene_name, name=None):
    """The numerical settings of preset `name` (default DEFAULT_NUMERICS) of a scene."""
    name = name or DEFAULT_NUMERICS
    scene(scene_name)  # a known scene
    presets = NUMERICS[scene_name]
    if name not in presets:
        raise ValueError(f"numerics={name!r} is unknown: valid values are {', '.join(sorted(presets))}")
    return dict(presets[name])


def pile_scene(name):
    """The scene whose piles scene `name` meshes (itself, or the one it crops)."""
    return scene(name).get("pile_of", name)


def pile_friction(name):
    """The friction the piles of scene `name` rose and settled at in phase 1
    (it names their files)."""
    return float(scene(pile_scene(name))["pile"]["mu_settle"])


def pile_rest_friction(name):
    """The lowest friction the piles of scene `name` are at rest at: the hold
    stage's (face contacts frozen, the rest sliding) if they had one."""
    pile = scene(pile_scene(name))["pile"]
    return float(pile.get("mu_hold", pile["mu_settle"]))


def scene(name):
    if name not in SCENES:
        raise ValueError(f"scene={name!r} is unknown: valid values are {', '.join(sorted(SCENES))}")
    return SCENES[name]
