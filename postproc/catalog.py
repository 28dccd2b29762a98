"""A set of runs of one model variant, grouped as the paper groups them: by ridge
(root attr ``ridge``), friction coefficient mu and bond shear strength tau_cr
(/parameters attrs), with each run's summary row computed once.

Besides the runs read from their files (``runs``), a catalog may hold runs known
by their summary rows only (``stored``: postproc/stored_rows.py). Every row is in
``rows`` (the tables read them all); select() and one() return the runs with
records unless asked for the stored ones too (``stored=True``: the figures
drawn from per-run values)."""
from dataclasses import dataclass, field

import numpy as np

from . import failure_plane, summary


class Missing(Exception):
    """A figure or table that cannot be made from the runs at hand (the message says why)."""


@dataclass
class Catalog:
    runs: list
    out_dir: str
    tau_ref: float = 50e3      # Pa: the paper's reference bond strength (Figs. 6-8, 12, 15-20a)
    mu_low: float = 0.05
    mu_high: float = 0.3
    plug_force: float = 11e3   # N/m, F_b of tau^(2)
    bond_points: str = failure_plane.DEFAULT_BOND_POINTS  # behind alpha and A_p (failure_plane)
    notes: list = field(default_factory=list)  # partial-figure remarks for MISSING.md
    rows: dict = field(default_factory=dict)
    stored: list = field(default_factory=list)  # runs known by their summary rows only

    def __post_init__(self):
        for r in self.runs:
            self.rows[r.path] = summary.summarize(r, self.plug_force, self.bond_points)
        for s in self.stored:
            self.rows[s.path] = s.with_strengths(self.plug_force)

    def row(self, run):
        return self.rows[run.path]

    @property
    def every_run(self):
        """The runs with records, then those known by their rows only."""
        return self.runs + self.stored

    def select(self, ridge=None, mu=None, tau_cr=None, stored=False):
        out = []
        for r in (self.every_run if stored else self.runs):
            if ridge is not None and r.ridge != ridge:
                continue
            if mu is not None and not np.isclose(r.mu, mu):
                continue
            if tau_cr is not None and not np.isclose(r.tau_cr, tau_cr):
                continue
            out.append(r)
        return out

    def one(self, ridge, mu, tau_cr, stored=False):
        sel = self.select(ridge, mu, tau_cr, stored)
        return sel[0] if sel else None

    def ridges(self, runs=None):
        return sorted({r.ridge for r in (runs if runs is not None else self.every_run)}, key=_ridge_key)

    def mus(self):
        return sorted({r.mu for r in self.every_run})

    def tau_crs(self):
        return sorted({r.tau_cr for r in self.every_run})

    def extreme_ridges(self, mu=None):
        """Ridges with the highest and lowest F^m at tau_ref and ``mu`` (default mu_low),
        the paper's choice for Figs. 6, 7 and 16 (Ridges 1 and 3). Raises Missing."""
        mu = self.mu_low if mu is None else mu
        sel = self.select(mu=mu, tau_cr=self.tau_ref)
        if not sel:
            raise Missing(f"no run with tau_cr = {self.tau_ref / 1e3:g} kPa and mu = {mu:g}")
        sel.sort(key=lambda r: -self.row(r)["F_m_kN_per_m"])
        return sel[0].ridge, sel[-1].ridge

    def reference_run(self):
        """The run of Figs. 12, 17-19: highest-F^m ridge at tau_ref, mu_low (the paper's Ridge 1)."""
        hi, _ = self.extreme_ridges()
        return self.one(hi, self.mu_low, self.tau_ref)


def _ridge_key(name):
    digits = "".join(c for c in name if c.isdigit())
    return (int(digits) if digits else 1 << 30, name)
