"""A set of runs of one model variant, grouped as the paper groups them: by ridge
(root attr ``ridge``), friction coefficient mu and bond shear strength tau_cr
(/parameters attrs), with each run's summary row computed once."""
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

    def __post_init__(self):
        for r in self.runs:
            self.rows[r.path] = summary.summarize(r, self.plug_force, self.bond_points)

    def row(self, run):
        return self.rows[run.path]

    def select(self, ridge=None, mu=None, tau_cr=None):
        out = []
        for r in self.runs:
            if ridge is not None and r.ridge != ridge:
                continue
            if mu is not None and not np.isclose(r.mu, mu):
                continue
            if tau_cr is not None and not np.isclose(r.tau_cr, tau_cr):
                continue
            out.append(r)
        return out

    def one(self, ridge, mu, tau_cr):
        sel = self.select(ridge, mu, tau_cr)
        return sel[0] if sel else None

    def ridges(self, runs=None):
        return sorted({r.ridge for r in (runs if runs is not None else self.runs)}, key=_ridge_key)

    def mus(self):
        return sorted({r.mu for r in self.runs})

    def tau_crs(self):
        return sorted({r.tau_cr for r in self.runs})

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
