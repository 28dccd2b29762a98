"""Run parameters of a punch-through simulation (paper Table 1) and their checks.

Every parameter has a default from Table 1 (or docs/model.md where the paper is
silent), a unit and a valid range. ``validate`` raises ValueError naming the
parameter and its range before any work starts, so a bad yade-batch line fails
in its first second rather than after an hour of settling.
"""
import math
from dataclasses import dataclass


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

    def range_text(self):
        if self.choices is not None:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        left = "(" if self.lo_open else "["
        right = ")" if self.hi_open else "]"
        lo = "-inf" if self.lo is None else repr(self.lo)
        hi = "inf" if self.hi is None else repr(self.hi)
        return f"{left}{lo}, {hi}{right}"


POS = dict(lo=0.0, lo_open=True)
NONNEG = dict(lo=0.0)

TABLE_1 = {
    # freeze bonds (values on top of the keel; they fall linearly to
    # strength_bottom_fraction of these at the keel bottom)
    "tau_cr": Parameter(50e3, "Pa", **POS, doc="bond shear strength at the keel top"),
    "sigma_cr": Parameter(10e3, "Pa", **POS, doc="bond tensile strength at the keel top"),
    "G": Parameter(15.0, "J/m^2", **POS, doc="bond fracture energy at the keel top"),
    "strength_bottom_fraction": Parameter(0.1, "-", lo=0.0, hi=1.0, lo_open=True,
                                          doc="bond strength and G at the keel bottom, as a fraction of the top value"),
    "force_direction": Parameter("paper", "-", choices=("paper", "work_conjugate"),
                                 doc="cohesive force direction: eq 11 as printed, or Ortiz-Pandolfi work-conjugate"),
    # contact and blocks
    "mu": Parameter(0.3, "-", **NONNEG, doc="Coulomb friction coefficient (ice-ice)"),
    "penalty": Parameter(2e11, "Pa", **POS, doc="contact penalty s (eq 2-3)"),
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
    "rho_w": Parameter(1010.0, "kg/m^3", **POS, doc="water density"),
    "drag_model": Parameter("quadratic", "-", choices=("linear", "quadratic", "none"),
                            doc="water drag law: linear -c_w v per block, quadratic form drag "
                                "-1/2 rho_w C_d |v| v L per block, or none (docs/model.md)"),
    "c_w": Parameter(2.5e4, "Pa s", **NONNEG, doc="linear water drag constant (drag_model='linear')"),
    "C_d": Parameter(1.0, "-", lo=0.0, hi=10.0,
                     doc="form drag coefficient (drag_model='quadratic'; ~1 for a bluff body, not in Table 1)"),
    "g": Parameter(9.81, "m/s^2", **POS, doc="gravitational acceleration"),
    # geometry
    "domain_width": Parameter(50.0, "m", **POS, doc="width of the consolidated layer and keel"),
    "keel_depth": Parameter(4.0, "m", **POS, doc="keel depth h below the consolidated layer"),
    "layer_thickness": Parameter(1.0, "m", **POS, doc="consolidated layer thickness"),
    "indenter_width": Parameter(4.0, "m", **POS, doc="indenter width w_I"),
    "indenter_thickness": Parameter(1.0, "m", **POS, doc="indenter thickness h_I"),
    # loading
    "v_final": Parameter(0.1, "m/s", **POS, doc="final indenter velocity"),
    "ramp_time": Parameter(2.0, "s", **NONNEG, doc="smooth acceleration time of the indenter"),
    "target_travel": Parameter(0.3, "m", **POS, doc="indenter travel y_I at which the run stops"),
    # numerics
    "dt": Parameter(1e-6, "s", **POS, doc="time step, checked against the stable step; in a yade-batch "
                    "table a dt column replaces the scene's dt_fraction x stable step"),
}


# The physical constants other modules need without a parameter dict (phase 1,
# analyses, tests): one home, the defaults above.
RHO_I = TABLE_1["rho_i"].default
RHO_W = TABLE_1["rho_w"].default
GRAVITY = TABLE_1["g"].default
LAYER_THICKNESS = TABLE_1["layer_thickness"].default


def defaults():
    return {k: p.default for k, p in TABLE_1.items()}


def check_value(name, value, spec=None):
    """Raise ValueError unless value is valid for parameter `name`."""
    spec = spec or TABLE_1[name]
    if spec.choices is not None:
        if value not in spec.choices:
            raise ValueError(f"parameter {name}={value!r} is invalid: valid values are {spec.range_text()}")
        return value
    # True is 1 to float(): a table's `mu True` would run at mu = 1
    if isinstance(value, bool):
        raise ValueError(f"parameter {name}={value!r} is a boolean, not a number; valid range "
                         f"{spec.range_text()} {spec.unit}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"parameter {name}={value!r} is not a number; valid range {spec.range_text()} {spec.unit}")
    bad = not math.isfinite(v)
    if spec.lo is not None:
        bad |= v < spec.lo or (spec.lo_open and v == spec.lo)
    if spec.hi is not None:
        bad |= v > spec.hi or (spec.hi_open and v == spec.hi)
    if bad:
        raise ValueError(f"parameter {name}={value!r} is out of range: valid range {spec.range_text()} {spec.unit}")
    return v


def require_range(name, value, lo=None, hi=None, lo_open=False):
    """check_value for a setting outside Table 1 (mesh sizes, tolerances): a
    finite number in [lo, hi] (lo excluded with lo_open)."""
    return check_value(name, value, Parameter(None, "", lo=lo, hi=hi, lo_open=lo_open))


def require_whole(name, value, lo=0):
    """A whole number >= lo (a seed, a count): refuses 1.5 and True, which
    int() would silently read as 1."""
    whole = isinstance(value, int) or (isinstance(value, float) and value.is_integer())
    if isinstance(value, bool) or not whole or value < lo:
        raise ValueError(f"{name}={value!r} must be a whole number >= {lo} ({lo}, {lo + 1}, {lo + 2}, ...)")
    return int(value)


class Checked(dict):
    """A full parameter dict that validate() has checked: passing it through
    validate() again returns a copy without checking twice."""


def validate(params):
    """Return a full, checked parameter dict: defaults overridden by `params`.

    Unknown names are an error too (a typo in a yade-batch table would
    otherwise silently run the default).
    """
    if isinstance(params, Checked):
        return Checked(params)
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
    if out["indenter_width"] >= out["domain_width"]:
        raise ValueError(f"parameter indenter_width={out['indenter_width']} must be smaller than "
                         f"domain_width={out['domain_width']} m")
    if out["rho_i"] >= out["rho_w"]:
        raise ValueError(f"parameter rho_i={out['rho_i']} must be below rho_w={out['rho_w']} kg/m^3: "
                         "the ice must float")
    return Checked(out)


def units():
    return {k: p.unit for k, p in TABLE_1.items()}


def water_line_draft(params):
    """Draft d of the freely floating consolidated layer: (ρ_i/ρ_w) t (docs/model.md §3.4)."""
    return params["rho_i"] / params["rho_w"] * params["layer_thickness"]
