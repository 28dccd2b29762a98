"""Every parameter of a punch-through run, declared once (issue 27).

One registry, REGISTRY: each parameter with its default (paper Table 1, or
docs/model.md where the paper is silent), unit, valid range, doc, group and
flags. Everything else derives from it:

- the columns a study table accepts and what ``validate`` takes (``table``);
- the run identity's parameter set (``identity``, run_identity.identity);
- the settle's key: a run differing from another only in parameters the
  settle never reads (``settle=False``: rest_states.SETTLE_FREE) loads its
  rest state (rest_states.settle_identity);
- the keys and defaults of the engine wrapper's Model.set (``engine``;
  icerubble/engine/model.py), and the engine's own check of them: the build
  writes these ranges into the C++ engine (tools/engine_parameter_header.py),
  which checks the one struct it is given against them;
- the parameter table of docs/parameters.md (``docs_table``; a test checks
  that the docs hold the registry's table).

Groups, by who reads the parameter:

- ``engine``: the physics the engine reads from the first step (contact,
  material, water, gravity) and its own switches;
- ``load``: read only once the loading starts (bond strengths, which no
  bond is checked against while settling, and the indenter's ramp);
- ``settle``: how the settle decides the scene is at rest (RunOptions);
- ``numerics``: the time step and what bounds it;
- ``mesh``: the geometry, which is the scene's mesh's: never a table
  column (pick a scene), recorded in a result's /parameters as measured on
  the mesh (files/mesh_file.mesh_geometry);
- ``pile``: phase 1 (yade_scripts/make_pile.py).

``validate`` raises ValueError naming the parameter and its range before any
work starts, so a bad yade-batch line fails in its first second rather than
after an hour of settling.
"""
import math
import numbers
from dataclasses import dataclass

GROUPS = ("pile", "mesh", "settle", "load", "numerics", "engine")


@dataclass(frozen=True)
class Parameter:
    default: object
    unit: str
    lo: float = None          # inclusive lower bound
    hi: float = None          # inclusive upper bound
    lo_open: bool = False     # lower bound excluded
    hi_open: bool = False     # upper bound excluded
    choices: tuple = None
    doc: str = ""
    group: str = "engine"
    kind: str = "number"      # number, flag (True/False), whole (an integer), choice, text
    inf_ok: bool = False      # a number may be +inf (contact_reach: the whole mesh)
    table: bool = True        # a column of a study table (validate takes it)
    identity: bool = True     # part of the run identity (run_identity.identity)
    settle: bool = True       # read by the settle (False: rest_states.SETTLE_FREE)
    engine: bool = False      # a key of the engine wrapper's Model.set
    bond: bool = False        # a bond strength: read by the settle only with settle_bonds='checked'

    def __post_init__(self):
        if self.group not in GROUPS:
            raise ValueError(f"group {self.group!r} is not one of {GROUPS}")
        if self.choices is not None and self.kind == "number":
            object.__setattr__(self, "kind", "choice")

    def range_text(self):
        if self.kind == "choice":
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind == "flag":
            return "True or False"
        if self.kind == "text":
            return "text"
        if self.kind == "whole":
            return f"a whole number >= {self.lo:g}" + ("" if self.hi is None else f" and <= {self.hi:d}")
        left = "(" if self.lo_open or self.lo is None else "["
        right = ")" if self.hi_open or (self.hi is None and not self.inf_ok) else "]"
        lo = "-inf" if self.lo is None else repr(self.lo)
        hi = "inf" if self.hi is None else repr(self.hi)
        return f"{left}{lo}, {hi}{right}"

    def rule_text(self):
        """The range in words: '> 0, finite', '>= 0 and < 1, finite', ..."""
        rules = []
        if self.lo is not None:
            rules.append(f"{'>' if self.lo_open else '>='} {self.lo:g}")
        if self.hi is not None:
            rules.append(f"{'<' if self.hi_open else '<='} {self.hi:g}")
        return " and ".join(rules) + ("" if self.inf_ok else (", " if rules else "") + "finite")


POS = dict(lo=0.0, lo_open=True)
NONNEG = dict(lo=0.0)
# what is never a table column nor part of the run identity: the engine's own
# switches and the geometry (the mesh's); a run sets them itself
NOT_TABLE = dict(table=False, identity=False)
SWITCH = dict(NOT_TABLE, kind="flag", engine=True)
# the largest count the engine holds (a 32-bit int)
INT32_MAX = 2**31 - 1

REGISTRY = {
    # freeze bonds (values on top of the keel; they fall linearly to
    # strength_bottom_fraction of these at the keel bottom); by default bonds
    # hold while the scene settles (none is checked) and the settle reads none
    # of these; with settle_bonds='checked' it reads them all (settle_free)
    "tau_cr": Parameter(50e3, "Pa", **POS, group="load", settle=False, bond=True, doc="bond shear strength at the keel top"),
    "sigma_cr": Parameter(10e3, "Pa", **POS, group="load", settle=False, bond=True,
                          doc="bond tensile strength at the keel top"),
    "G": Parameter(15.0, "J/m^2", **POS, group="load", settle=False, bond=True, doc="bond fracture energy at the keel top"),
    "strength_bottom_fraction": Parameter(0.1, "-", lo=0.0, hi=1.0, lo_open=True, group="load", settle=False, bond=True,
                                          doc="bond strength and G at the keel bottom, as a fraction of the top value"),
    # work-conjugate by default: Table 3's count of failure modes at 300 mm and its rise
    # with tau_cr, and Table 2's first peak, are the paper's with it, not with the
    # printed form (docs/model.md §3.3, docs/study_paper_depth.md)
    "force_direction": Parameter("work_conjugate", "-", choices=("paper", "work_conjugate"), group="load",
                                 settle=False, bond=True,
                                 doc="cohesive force direction: eq 11 as printed ('paper'), or Ortiz-Pandolfi "
                                     "work-conjugate (beta^2 on the tangential opening)"),
    # contact and blocks
    "mu": Parameter(0.3, "-", **NONNEG, engine=True, doc="Coulomb friction coefficient (ice-ice)"),
    "penalty": Parameter(2e11, "Pa", **POS, engine=True, doc="contact penalty s (eq 2-3)"),
    "E": Parameter(2e9, "Pa", **POS, doc="Young's modulus of blocks, layer and indenter"),
    "nu": Parameter(0.3, "-", lo=0.0, hi=0.5, hi_open=True, doc="Poisson's ratio (not given in the paper)"),
    "rho_i": Parameter(920.0, "kg/m^3", **POS, doc="ice density"),
    "damping": Parameter(0.0, "-", **NONNEG, doc="element strain-rate damping, fraction of critical at the element scale"),
    # Table 1's "water: viscous damping constant 2.5e4 Pa s", read as the blocks'
    # viscosity; the linear-drag reading made F a drag record (docs/model.md 3.4)
    "viscosity": Parameter(2.5e4, "Pa s", **NONNEG,
                           doc="viscosity of the block material: viscous stress eta x rate of Green "
                               "strain (~ eta D); Table 1's 'viscous damping constant' (docs/model.md 3.4)"),
    # water
    "rho_w": Parameter(1010.0, "kg/m^3", **POS, engine=True, doc="water density"),
    "drag_model": Parameter("quadratic", "-", choices=("linear", "quadratic", "none"), engine=True,
                            doc="water drag law: linear -c_w v per block, quadratic form drag "
                                "-1/2 rho_w C_d |v| v L per block, or none (docs/model.md)"),
    "c_w": Parameter(2.5e4, "Pa s", **NONNEG, engine=True, doc="linear water drag constant (drag_model='linear')"),
    "C_d": Parameter(1.0, "-", lo=0.0, hi=10.0, engine=True,
                     doc="form drag coefficient (drag_model='quadratic'; ~1 for a bluff body, not in Table 1)"),
    "g": Parameter(9.81, "m/s^2", **POS, engine=True, doc="gravitational acceleration"),
    # geometry: the scene's mesh's (refused in a table: pick a scene)
    "domain_width": Parameter(50.0, "m", **POS, group="mesh", **NOT_TABLE,
                              doc="width of the consolidated layer and keel"),
    "keel_depth": Parameter(4.0, "m", **POS, group="mesh", **NOT_TABLE,
                            doc="keel depth h below the consolidated layer"),
    "layer_thickness": Parameter(1.0, "m", **POS, group="mesh", **NOT_TABLE, doc="consolidated layer thickness"),
    "indenter_width": Parameter(4.0, "m", **POS, group="mesh", **NOT_TABLE, doc="indenter width w_I"),
    "indenter_thickness": Parameter(1.0, "m", **POS, group="mesh", **NOT_TABLE, doc="indenter thickness h_I"),
    # loading
    "v_final": Parameter(0.1, "m/s", **POS, group="load", settle=False, doc="final indenter velocity"),
    "ramp_time": Parameter(2.0, "s", **NONNEG, group="load", settle=False,
                           doc="smooth acceleration time of the indenter"),
    "target_travel": Parameter(0.3, "m", **POS, group="load", settle=False,
                               doc="indenter travel y_I at which the run stops"),
    # numerics
    "dt": Parameter(1e-6, "s", **POS, group="numerics", engine=True,
                    doc="time step, checked against the stable step; in a yade-batch "
                    "table a dt column replaces the scene's dt_fraction x stable step"),
    # --- the engine's own settings (engine.Model.set; not table columns: a
    # run sets them from its scene and numerics, RunOptions)
    "dt_fraction": Parameter(None, "-", lo=0.0, hi=1.0, lo_open=True, group="numerics", engine=True, **NOT_TABLE,
                             doc="time step as this fraction of the stable step at the moment it is set "
                                 "(masses scaled); fixed after, like an explicit dt, which replaces it"),
    "mass_scaling_dt": Parameter(0.0, "s", **NONNEG, group="numerics", engine=True, **NOT_TABLE,
                                 doc="selective mass scaling: add inertial mass (not weight) to the nodes that "
                                     "limit the stable step so that it is >= this; 0 = off"),
    "contact_reach": Parameter(math.inf, "m", **POS, inf_ok=True, group="numerics", engine=True, **NOT_TABLE,
                               doc="the contact stable step counts only the boundaries within this distance of "
                                   "each edge; inf = the whole mesh (re-checked as nodes move, docs/engine_api.md)"),
    "check_stable_dt": Parameter(True, "-", group="numerics", **SWITCH, doc="refuse dt above the stable step"),
    "check_energy": Parameter(True, "-", group="numerics", **SWITCH,
                              doc="stop when energy grows without a source"),
    "energy_tolerance": Parameter(0.1, "-", **POS, group="numerics", engine=True, **NOT_TABLE,
                                  doc="stop when the energy balance residual exceeds this fraction of the "
                                      "energy terms"),
    "threads": Parameter(0, "-", lo=0, hi=INT32_MAX, kind="whole", group="numerics", engine=True, **NOT_TABLE,
                         doc="OpenMP threads, 0 = OMP_NUM_THREADS / all cores as the process started "
                             "(openmp_threads.default_threads, whatever changed OpenMP's setting since)"),
    "gravity": Parameter(True, "-", **SWITCH, doc="gravity on/off"),
    "buoyancy": Parameter(False, "-", **SWITCH, doc="buoyancy on/off"),
    "drag": Parameter(False, "-", **SWITCH, doc="water drag on/off (the law is drag_model)"),
    "y_w": Parameter(0.0, "m", engine=True, **NOT_TABLE,
                     doc="water line (a run's: where its consolidated layer floats freely)"),
    "local_damping": Parameter(0.0, "-", lo=0.0, hi=1.0, hi_open=True, engine=True, **NOT_TABLE,
                               doc="local non-viscous (Cundall) damping, for reaching rest; its work is "
                                   "booked as damping"),
    "sleeping": Parameter(False, "-", **SWITCH, doc="sleeping far field on/off: bodies at rest are held and "
                          "their triangles not computed (engine/src/model/sleeping.hpp)"),
    "sleep_velocity": Parameter(1e-4, "m/s", **NONNEG, engine=True, **NOT_TABLE,
                                doc="a body is at rest when every node of it is slower than this, ..."),
    "sleep_force": Parameter(1e-3, "-", **NONNEG, engine=True, **NOT_TABLE,
                             doc="... and its mean resultant force and moment are below this fraction of its "
                                 "weight; an asleep node wakes when its force changes by this fraction of its "
                                 "own weight"),
    "sleep_quiet_steps": Parameter(100, "-", lo=1, hi=INT32_MAX, kind="whole", engine=True, **NOT_TABLE,
                                   doc="... over a window of this many steps"),
    # --- the settle (RunOptions; not in the run identity: every study's
    # defaults, but a rest state is shared only under the same ones)
    # how the bonds take the settle: part of the run identity and read by the
    # settle, so a table column (issue 26: the deep scene's rest state with
    # every bond held had 27-36 points past eq 5, which let go at the first
    # check and spread a cascade of splits across the keel)
    "settle_bonds": Parameter("held", "-", choices=("held", "checked"), group="settle",
                              doc="freeze bonds while settling: 'held' (none is checked; the rest state is "
                                  "shared by runs that differ in bond strength) or 'checked' (eq 5 is "
                                  "checked from the first step, so the loading starts from a balance "
                                  "the bonds can carry; points that split then belong to the initial state)"),
    # the ends of a scene that its crop did not cut: phase 1's walls stood there
    # (issue 26: the paper scene's ridge 2 was not at rest after 5 s, the blocks
    # against both walls sliding out and up at 0.1-0.2 m/s)
    "side_walls": Parameter("free", "-", choices=("free", "held"), group="settle",
                            doc="the pile's ends where phase 1's walls stood (an uncropped scene's |x| = W/2): "
                                "'free' (no walls in the punch-through phase) or 'held' (each block node within "
                                "1 cm of a wall held in x, free in y, as a cropped scene's cut faces are)"),
    # the indenter while settling (issue 26: at mu 0.05 and tau_cr 5 kPa the
    # keel's buoyant part under a free indenter broke loose and lifted it 12 cm,
    # and the settle never ended; held, it came to rest)
    "settle_indenter": Parameter("free", "-", choices=("free", "held"), group="settle",
                                 doc="the indenter while settling: 'free' (it finds its balance on the keel, "
                                     "then is held where it came to rest: F at rest ~0) or 'held' (held where "
                                     "it was meshed from the first step, as a displacement-driven indenter "
                                     "that has not moved; the keel's push on it at rest is F at rest)"),
    "settle_max_time": Parameter(5.0, "s", **POS, group="settle", **NOT_TABLE,
                                 doc="the settle stops, saying so, if not at rest after this simulated time"),
    "settle_min_time": Parameter(0.05, "s", **NONNEG, group="settle", **NOT_TABLE,
                                 doc="the settle runs at least this long (at most settle_max_time)"),
    "settle_velocity": Parameter(1e-4, "m/s", **POS, group="settle", **NOT_TABLE,
                                 doc="at rest: every node slower than this"),
    "settle_accel": Parameter(1e-4, "g", **POS, group="settle", **NOT_TABLE,
                              doc="at rest: a free body's mean acceleration over a check interval below this"),
    "settle_hold_time": Parameter(0.02, "s", **POS, group="settle", **NOT_TABLE,
                                  doc="the indenter is held at rest this long before its force is checked"),
}


# Phase 1's parameters (yade_scripts/make_pile.py: the pile, made in YADE),
# declared here beside the run's: a pile table's columns, their defaults (the
# demo pile's) and ranges. domain_width and keel_depth here are what phase 1
# aims at; the run's (group mesh) are what the mesh it made measures. Phase 1
# also reads the run registry's rho_i, rho_w, g and layer_thickness (PILE_SHARED).
PILE_ONLY = dict(group="pile", table=False, identity=False, settle=False)
PILE = {
    "seed": Parameter(1, "-", lo=0, kind="whole", **PILE_ONLY,
                      doc="random generator seed (block sizes, tilts, velocities)"),
    "domain_width": Parameter(10.0, "m", **POS, **PILE_ONLY, doc="keel width between the side walls (paper: 50)"),
    "n_blocks": Parameter(0, "-", lo=0, kind="whole", **PILE_ONLY,
                          doc="number of blocks; 0: from keel_depth and porosity_guess"),
    "keel_depth": Parameter(1.8, "m", **POS, **PILE_ONLY, doc="target keel depth when n_blocks = 0 (paper: ~4)"),
    "porosity_guess": Parameter(0.25, "-", lo=0.0, hi=0.95, **PILE_ONLY,
                                doc="porosity used only to count blocks for keel_depth (paper: ~0.25)"),
    "t_min": Parameter(0.2, "m", **POS, **PILE_ONLY, doc="block thickness range, lower end (paper Table 1)"),
    "t_max": Parameter(0.4, "m", **POS, **PILE_ONLY, doc="block thickness range, upper end (>= t_min)"),
    "l_min": Parameter(0.6, "m", **POS, **PILE_ONLY, doc="block length range, lower end (>= t_max; paper Table 1)"),
    "l_max": Parameter(1.8, "m", **POS, **PILE_ONLY, doc="block length range, upper end (>= l_min)"),
    "max_tilt": Parameter(30.0, "deg", lo=0.0, hi=90.0, **PILE_ONLY, doc="initial random tilt range +-"),
    "v_max": Parameter(0.2, "m/s", **NONNEG, **PILE_ONLY, doc="initial random speed (uniform direction)"),
    "w_max": Parameter(0.5, "rad/s", **NONNEG, **PILE_ONLY, doc="initial random spin range +-"),
    "mu_settle": Parameter(0.05, "-", lo=0.0, hi=2.0, **PILE_ONLY,
                           doc="friction coefficient while the blocks rise and settle"),
    "mu_hold": Parameter(-1.0, "-", hi=2.0, **PILE_ONLY,
                         doc="then at rest under this friction (<= mu_settle) with face contacts frozen; "
                             "< 0: no hold stage"),
    "hold_bond_length": Parameter(0.05, "m", **POS, **PILE_ONLY,
                                  doc="a contact this long is a face contact (the mesher's min_bond_length)"),
    "hold_from": Parameter("", "-", kind="text", **PILE_ONLY,
                           doc="a pile file: skip the rise, hold its blocks (its own parameters are kept)"),
    "E_settle": Parameter(2e6, "Pa", **POS, **PILE_ONLY,
                          doc="contact Young's modulus for settling (k_n = E/2 per m^3)"),
    "damping": Parameter(0.5, "-", lo=0.0, hi=0.99, **PILE_ONLY, doc="Cundall local damping of NewtonIntegrator"),
    "dt_safety": Parameter(0.5, "-", lo=0.0, hi=1.0, lo_open=True, **PILE_ONLY,
                           doc="fraction of the critical step of a block chain"),
    "ke_per_block": Parameter(1e-4, "J/m", **POS, **PILE_ONLY,
                              doc="settled when kinetic energy / n_blocks stays below this"),
    "check_interval": Parameter(0.25, "s", **POS, **PILE_ONLY, doc="simulated time between kinetic-energy checks"),
    "n_quiet": Parameter(4, "-", lo=1, kind="whole", **PILE_ONLY, doc="consecutive quiet checks required"),
    "max_time": Parameter(300.0, "s", **POS, **PILE_ONLY,
                          doc="simulated time after which phase 1 gives up (writes settled=0)"),
    "out": Parameter("", "-", kind="text", **PILE_ONLY,
                     doc="output file; '' -> pile_<description>.h5 or pile.h5"),
}
PILE_SHARED = ("rho_i", "rho_w", "g", "layer_thickness")


def _select(**flags):
    return {k: p for k, p in REGISTRY.items() if all(getattr(p, f) == v for f, v in flags.items())}


# The run parameters: a study table's parameter columns, what validate takes.
TABLE_1 = _select(table=True)
# Geometry: the scene's mesh's, recorded in the result as measured on it.
MESH = _select(group="mesh")
# The engine wrapper's keys (engine.Model.set) and defaults; the engine checks their ranges.
ENGINE = _select(engine=True)
# Run parameters the settle never reads (rest_states.py).
SETTLE_FREE = tuple(k for k, p in TABLE_1.items() if not p.settle)
# The settle's own options (RunOptions), part of the settle's key.
SETTLE_OPTIONS = tuple(_select(group="settle", table=False))
# The bond strengths, read by a settle with settle_bonds='checked'.
BOND_STRENGTH = tuple(_select(bond=True))


def settle_free(params):
    """The run parameters the settle of `params` never reads: SETTLE_FREE, less
    the bond strengths where the bonds are checked while settling."""
    if params.get("settle_bonds", REGISTRY["settle_bonds"].default) == "checked":
        return tuple(k for k in SETTLE_FREE if k not in BOND_STRENGTH)
    return SETTLE_FREE


# The physical constants other modules need without a parameter dict (phase 1,
# analyses, tests): one home, the defaults above.
RHO_I = REGISTRY["rho_i"].default
RHO_W = REGISTRY["rho_w"].default
GRAVITY = REGISTRY["g"].default
LAYER_THICKNESS = REGISTRY["layer_thickness"].default
DRAG_MODELS = REGISTRY["drag_model"].choices
FORCE_DIRECTIONS = REGISTRY["force_direction"].choices
# the form of eq 11 a run does not take unless asked (tests change to it)
OTHER_FORCE_DIRECTION = next(d for d in FORCE_DIRECTIONS if d != REGISTRY["force_direction"].default)


def defaults():
    """The run parameters' defaults (Table 1's)."""
    return {k: p.default for k, p in TABLE_1.items()}


def check_value(name, value, spec=None):
    """Raise ValueError unless value is valid for parameter `name`; return it
    as the run reads it (a float, a bool, an int, one of the choices)."""
    spec = spec or REGISTRY[name]
    if spec.kind == "choice":
        if value not in spec.choices:
            raise ValueError(f"parameter {name}={value!r} is invalid: valid values are {spec.range_text()}")
        return value
    if spec.kind == "flag":
        if not isinstance(value, bool) and type(value).__name__ != "bool_":   # numpy's bool too
            raise ValueError(f"{name} must be True or False (got {value!r})")
        return bool(value)
    if spec.kind == "whole":
        return require_whole(name, value, lo=int(spec.lo), hi=spec.hi)
    if spec.kind == "text":
        if not isinstance(value, str):
            raise ValueError(f"parameter {name}={value!r} must be text")
        return value
    # True is 1 to float(): a table's `mu True` would run at mu = 1
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        raise ValueError(f"parameter {name}={value!r} is a boolean, not a number; valid range "
                         f"{spec.range_text()} {spec.unit}")
    # a number, not text that reads as one (float() would take '1e-6')
    if not isinstance(value, numbers.Real):
        raise ValueError(f"parameter {name}={value!r} is not a number; valid range {spec.range_text()} {spec.unit}")
    v = float(value)
    bad = not (math.isfinite(v) or (spec.inf_ok and v == math.inf))
    if spec.lo is not None:
        bad |= v < spec.lo or (spec.lo_open and v == spec.lo)
    if spec.hi is not None:
        bad |= v > spec.hi or (spec.hi_open and v == spec.hi)
    if bad:
        raise ValueError(f"parameter {name}={value!r} is out of range: valid range {spec.range_text()} {spec.unit} "
                         f"({spec.rule_text()})")
    return v


def require_range(name, value, lo=None, hi=None, lo_open=False):
    """check_value for a setting outside the registry (mesh sizes, tolerances):
    a finite number in [lo, hi] (lo excluded with lo_open)."""
    return check_value(name, value, Parameter(None, "", lo=lo, hi=hi, lo_open=lo_open))


def require_whole(name, value, lo=0, hi=None):
    """A whole number >= lo (and <= hi where given: a seed, a count): refuses
    1.5 and True, which int() would silently read as 1."""
    whole = isinstance(value, numbers.Integral) or (isinstance(value, float) and value.is_integer())
    if isinstance(value, bool) or type(value).__name__ == "bool_" or not whole or value < lo:
        raise ValueError(f"{name}={value!r} must be a whole number >= {lo} ({lo}, {lo + 1}, {lo + 2}, ...)")
    if hi is not None and value > hi:
        raise ValueError(f"{name}={value!r} must be a whole number <= {hi:d}")
    return int(value)


class Checked(dict):
    """A full parameter dict that validate() has checked: passing it through
    validate() again returns a copy without checking twice."""


def geometry_refused(names, scenes=()):
    """The message for geometry asked of a table or of validate: the geometry
    is the scene's mesh's. scenes: the scenes to name (run/presets.SCENES,
    which this base module cannot import)."""
    which = f" ({', '.join(sorted(scenes))}; icerubble/run/presets.py)" if scenes else \
        " (icerubble/run/presets.py SCENES; a table's scene column)"
    return (f"{', '.join(names)} {'is' if len(names) == 1 else 'are'} the scene's geometry, taken from its "
            f"mesh: not a run parameter; to change the geometry pick a scene{which}")


def validate(params, scenes=()):
    """Return a full, checked parameter dict: defaults overridden by `params`.

    Unknown names are an error too (a typo in a yade-batch table would
    otherwise silently run the default); so is geometry (the scene's mesh's:
    the message names `scenes`, run/presets.SCENES where the caller knows them).
    """
    if isinstance(params, Checked):
        return Checked(params)
    geometry = sorted(set(params) & set(MESH))
    if geometry:
        raise ValueError(geometry_refused(geometry, scenes))
    unknown = sorted(set(params) - set(TABLE_1))
    if unknown:
        raise ValueError(f"unknown parameter(s) {', '.join(unknown)}; known: {', '.join(sorted(TABLE_1))}")
    out = defaults()
    for name, value in params.items():
        out[name] = check_value(name, value)
    # a drag constant set away from its default for a law that does not use
    # it is a mistake in the table (validate also sees full dicts: defaults pass)
    for name, law in (("c_w", "linear"), ("C_d", "quadratic")):
        if out[name] != TABLE_1[name].default and out["drag_model"] != law:
            raise ValueError(f"parameter {name}={params[name]!r} is used only with drag_model='{law}' "
                             f"(got drag_model={out['drag_model']!r}); drop {name} or set drag_model")
    if out["rho_i"] >= out["rho_w"]:
        raise ValueError(f"parameter rho_i={out['rho_i']} must be below rho_w={out['rho_w']} kg/m^3: "
                         "the ice must float")
    return Checked(out)


def recorded(params, geometry):
    """The run parameters with the geometry measured on the mesh
    (files/mesh_file.mesh_geometry), in the registry's order: what a result's
    /parameters records."""
    both = dict(params, **geometry)
    return Checked({k: both[k] for k in REGISTRY if k in both})


def units():
    return {k: p.unit for k, p in REGISTRY.items()}


def water_line_draft(params, layer_thickness=LAYER_THICKNESS):
    """Draft d of the freely floating consolidated layer: (ρ_i/ρ_w) t (docs/model.md §3.4)."""
    return params["rho_i"] / params["rho_w"] * layer_thickness


def docs_table():
    """The registry as the markdown table of docs/parameters.md, one row per
    parameter, grouped as GROUPS."""
    rows = ["| parameter | group | default | unit | valid | table column | identity | settle reads | doc |",
            "|---|---|---|---|---|---|---|---|---|"]
    yes = {True: "yes", False: "no"}
    for group in GROUPS:
        for k, p in (PILE if group == "pile" else REGISTRY).items():
            if p.group != group:
                continue
            rows.append(f"| `{k}` | {group} | {p.default!r} | {p.unit} | {p.range_text()} | {yes[p.table]} | "
                        f"{yes[p.identity]} | {yes[p.settle] if p.table else '-'} | {p.doc.replace('|', '/')} |")
    return "\n".join(rows) + "\n"


DOCS_HEAD = """# Run parameters

Generated from the registry of `icerubble/parameters.py` (`/usr/bin/python3 -m
icerubble.parameters > docs/parameters.md`); `tests/test_parameters.py` checks that
this page is the registry's. Each parameter is declared there once: its default,
unit, range, doc, group and flags, from which the study table's columns, the run
identity, the settle's key (rest_states.py), the engine wrapper's `Model.set`, the ranges the
C++ engine checks (written into it by the build) and this table derive.

- **table column**: a column of a study table (a yade-batch line), what
  `parameters.validate` takes; the rest a run sets itself (its scene and numerics).
- **identity**: part of the run identity (run_identity.py), the hash that names the
  run's result. The geometry (group mesh) is not: it is the scene's mesh's, which the
  identity holds as the mesh digest. Identities made before issue 27 held Table 1's
  geometry (keel_depth = 4.0 whatever the mesh): the same run has another run id today.
- **settle reads**: no: the settle never reads it (rest_states.SETTLE_FREE), so runs
  differing only in these share a rest state.
- **group pile**: phase 1's (`yade_scripts/make_pile.py`), the columns of a pile table;
  phase 1 also reads `rho_i`, `rho_w`, `g` and `layer_thickness` from the run's.
- **group mesh**: refused as a table column and by `validate`, with a message naming
  the scenes: to change the geometry, pick a scene (icerubble/run/presets.py).
  A result's /parameters records the geometry as measured on the mesh.

"""


if __name__ == "__main__":
    print(DOCS_HEAD + docs_table(), end="")
