"""The settle of a punch-through run (paper section 2.4: "before any indenter
motion, it was ensured that the system was in balance"; docs/model.md §4).

Damped motion to rest under gravity and buoyancy with the indenter free (or,
settle_indenter='held', held where it was meshed), the check that every free
body is in balance, and the hold that measures the
force at rest; then the run's loading starts. ``Settle(run).run()`` does it
for a PunchThrough ``run`` (run/punch_through_run.py), whose model, options,
parameters and RunState it reads and moves on.
"""
import math

import numpy as np

from .progress import Progress, bond_text, settle_eta_text

SETTLE_CHECK_INTERVAL = 2e-3  # s simulated between two at-rest checks
SETTLE_LOCAL_DAMPING = 0.7     # Cundall damping while settling (YADE's default is 0.2)


class Settle:
    """The settle of `run`, and the node -> body maps its balance check and
    the block moves use."""

    def __init__(self, run):
        self.driver = run
        self.node_bodies(run.scene.model)

    def node_bodies(self, m):
        """node -> body, body weights, sizes and which bodies are held, for the
        settle's balance check and the block moves; again after bond points
        split (a split adds nodes).

        The engine's rule (sleeping): a node shared by bonded bodies belongs
        to the body of its lowest-numbered triangle."""
        tri = np.asarray(m.triangles)
        first = np.full(m.n_nodes, len(tri), np.int64)
        np.minimum.at(first, tri.ravel(), np.repeat(np.arange(len(tri)), 3))
        self.node_body = np.where(first < len(tri), np.append(np.asarray(m.body), -1)[first], -1)
        # sqrt(area) of each body: the moment arm of the settle's balance check
        area = np.bincount(np.asarray(m.body), weights=np.asarray(m.area0), minlength=len(self.driver.scene.body_kind))
        self.body_size = np.sqrt(area)
        own = self.node_body >= 0
        self.body_weight = np.bincount(self.node_body[own], minlength=len(self.driver.scene.body_kind),
                                        weights=np.asarray(m.mass_phys)[own] * self.driver.params["g"])
        self.body_held = np.zeros(len(self.driver.scene.body_kind), bool)
        self.body_held[self.node_body[m.node_sets["layer_top"]]] = True
        if self.indenter_held():   # its balance is the rig's: not checked
            self.body_held[self.node_body[m.node_sets["indenter_top"]]] = True

    def momenta(self):
        """Each body's momentum and angular momentum about its centre of
        weight, with that centre: ((P (B, 2), L (B,)), centre (B, 2))."""
        m = self.driver.model
        n = len(self.node_body)
        nb, own = self.node_body, self.node_body >= 0
        B = len(self.driver.scene.body_kind)
        x, mg = m.positions[:n], m.mass_phys[:n] * self.driver.params["g"]
        c = np.stack([np.bincount(nb[own], weights=(mg * x[:, k])[own], minlength=B) for k in (0, 1)], axis=1)
        c /= self.body_weight[:, None]
        return self.momenta_about(c), c

    def momenta_about(self, c):
        """(P (B, 2), L (B,)): momenta with the inertial masses, L about the
        points c (B, 2)."""
        m = self.driver.model
        n = len(self.node_body)
        nb, own = self.node_body, self.node_body >= 0
        B = len(self.driver.scene.body_kind)
        x, v, mass = m.positions[:n], m.velocities[:n], m.mass[:n]
        r = x - c[np.maximum(nb, 0)]
        p = mass[:, None] * v
        P = np.stack([np.bincount(nb[own], weights=p[own, 0], minlength=B),
                      np.bincount(nb[own], weights=p[own, 1], minlength=B)], axis=1)
        L = np.bincount(nb[own], weights=(r[:, 0] * p[:, 1] - r[:, 1] * p[:, 0])[own], minlength=B)
        return P, L

    def out_of_balance(self, before, duration):
        """(largest free node speed [m/s], largest out-of-balance of a free body
        [-], that body) over the steps since ``before`` = self.momenta().

        A body is out of balance by the mean resultant of its loads over those
        steps (its change of momentum over their duration: the integrator
        conserves momentum exactly) over its weight, or by the mean resultant
        moment about its centre (the change of its angular momentum) over its
        weight times its size sqrt(A), whichever is larger. Internal forces
        cancel in both, so this is the body's own equilibrium under contact,
        bonds, weight and buoyancy, and the mean takes out vibration faster
        than the check interval. An instantaneous per-node check held the
        paper scene's settle for ever: when every block was in balance to
        3e-5, ~100 nodes of tiny elements in the layer and indenter still shook
        at 10 g (amplitude 1e-11 m) and the indenter's friction springs rang at
        2 % of its weight. Bodies with a held node (the layer) balance on their
        support: only their speed counts."""
        m = self.driver.model
        n = len(self.node_body)
        (P0, L0), c = before
        P1, L1 = self.momenta_about(c)
        weight = self.body_weight
        imbalance = np.maximum(np.hypot(*(P1 - P0).T), np.abs(L1 - L0) / self.body_size) / (duration * weight)
        imbalance[self.body_held] = 0.0
        worst = int(np.argmax(imbalance))
        return float(np.hypot(*m.velocities[:n].T).max()), float(imbalance[worst]), worst

    def block_sums(self):
        """(ids, node counts, sums of u_x, sums of u_y) of each block's nodes:
        their move from where the mesh put them (before loading: while settling)."""
        m = self.driver.model
        nb = len(self.driver.scene.body_kind)
        nb_nodes = self.node_body
        u = np.asarray(m.positions)[:len(nb_nodes)] - np.asarray(m.reference_positions)[:len(nb_nodes)]
        ok = nb_nodes >= 0
        cnt = np.maximum(np.bincount(nb_nodes[ok], minlength=nb), 1)
        ux = np.bincount(nb_nodes[ok], weights=u[ok, 0], minlength=nb)
        uy = np.bincount(nb_nodes[ok], weights=u[ok, 1], minlength=nb)
        ids = np.flatnonzero(self.driver.scene.body_kind == 0)
        return ids, cnt[ids], ux[ids], uy[ids]

    def block_moves(self):
        """(ids, distances [m]): how far each block's node centroid is from
        where the mesh put it (before loading: its move while settling)."""
        ids, cnt, ux, uy = self.block_sums()
        return ids, np.hypot(ux, uy) / cnt

    def block_displacements(self):
        """(ids, u_x, u_y) [m] of each block's node centroid, as block_moves."""
        ids, cnt, ux, uy = self.block_sums()
        return ids, ux / cnt, uy / cnt

    def body_kind_name(self, b):
        return ("a block", "the consolidated layer", "the indenter")[int(self.driver.scene.body_kind[b])]

    def fastest_block_text(self):
        m = self.driver.model
        v = np.hypot(*m.velocities.T)[:len(self.node_body)]
        b = int(self.node_body[int(np.argmax(v))])
        ids, d = self.block_moves()
        moved = d[ids == b][0] if b in ids else math.nan
        return f"fastest node on body {b} (moved {moved * 1e3:.1f} mm while settling)"

    def run(self):
        """Damped motion to rest under gravity and buoyancy, the indenter free
        (settle_indenter='free', then held where it came to rest) or held
        where it was meshed ('held').

        Drag is off and local non-viscous damping (Cundall; each node's force
        reduced by SETTLE_LOCAL_DAMPING x its size when it pushes along the
        node's motion) takes the energy out instead: it damps every frequency
        alike, the light nodes' fast contact vibrations as well as a loose
        block floating up to its support, which drag would let rise at its
        ~1 cm/s terminal speed. At rest neither does work, so the equilibrium
        is the same. Loading starts with drag on and local damping off.
        """
        m, o = self.driver.model, self.driver.options
        if o.settle_mass_scaling_dt is not None:
            self.settle_step(True)
        dt = m.dt
        self.driver.apply_boundary_conditions()
        if self.indenter_held():   # where it was meshed (the loading's hold below keeps it there)
            self.hold_indenter()
        # settle_bonds: 'held' keeps every bond (the scene's default, check off);
        # 'checked' lets a point past eq 5 split now, so the loading starts
        # from a balance the bonds can carry
        checked = self.driver.params["settle_bonds"] == "checked"
        m.set_bond_params(check_failure=checked)
        chunk = max(1, int(round(SETTLE_CHECK_INTERVAL / dt)))
        if self.driver.state.t_settle is None or not math.isfinite(self.driver.state.t_settle):
            self.driver.state.t_settle = m.time   # kept in checkpoints: a resumed settle counts from here too
        t_start = self.driver.state.t_settle
        prog = Progress("settle", m.step_count, every_s=o.progress_every_s,
                        eta=lambda t, rate: settle_eta_text(t, o.settle_max_time, dt, rate))
        while True:
            if m.n_nodes != len(self.node_body):   # points split (settle_bonds='checked'), or a resumed settle
                self.node_bodies(m)
            before, t0 = self.momenta(), m.time
            m.step(chunk)
            split = m.n_nodes != len(self.node_body)
            vmax, imbalance, body = self.out_of_balance(before, m.time - t0)
            t_rel = m.time - t_start
            prog.update(m.step_count, t_rel, lambda: f"max speed {vmax:.2g} m/s (at rest < {o.settle_velocity:g})"
                        f"  out of balance {imbalance:.2g} (< {o.settle_accel:g})"
                        + (f"  {bond_text(m)}" if checked else ""))
            # at rest = slow AND in balance: a low speed alone is also what the
            # first steps after switching gravity on look like; a chunk in which
            # points split is not at rest (and its momenta were summed over the
            # nodes before the split)
            if t_rel >= o.settle_min_time and vmax < o.settle_velocity and imbalance < o.settle_accel and not split:
                break
            if t_rel >= o.settle_max_time:
                hint = ""
                if self.driver.params["mu"] < self.driver.pile_rest_friction:
                    hint = (f"; the pile was settled at friction {self.driver.pile_rest_friction:g} > mu = "
                            f"{self.driver.params['mu']:g}: make it at the lowest mu it is run at (mu_settle)")
                raise RuntimeError(
                    f"the scene did not come to rest within settle_max_time={o.settle_max_time} s: "
                    f"max node speed {vmax:.3g} m/s (settle_velocity={o.settle_velocity}), "
                    f"largest out-of-balance of a free body {imbalance:.3g} of its weight (body {body}, "
                    f"{self.body_kind_name(body)}; settle_accel={o.settle_accel}); "
                    f"{self.fastest_block_text()}{hint}; a settle allowed longer: icerubble study run "
                    f"--settle-max-time S")
            self.driver._maybe_checkpoint()
        self.driver.state.settle_time = m.time - t_start
        self.driver.state.settle_max_speed = vmax
        self.driver.state.settle_max_block_move = float(self.block_moves()[1].max(initial=0.0))
        self.driver.state.settle_splits = int(m.bonds.counts["split"])
        if o.settle_mass_scaling_dt is not None:
            self.settle_step(False)
            dt = m.dt
        m.set(drag=True, local_damping=0.0)
        # Hold the indenter where it came to rest and measure what holding it
        # takes: ~0 if the system is in balance (paper 2.4). The first steps
        # of the hold carry the impulse of the residual speed, so average the
        # force over the second half of the hold.
        if not self.indenter_held():   # held since the first step otherwise
            self.hold_indenter()
        n_hold = max(2, int(round(o.settle_hold_time / dt)))
        m.step(n_hold // 2)
        forces = []
        for _ in range(10):
            m.step(max(1, n_hold // 20))
            forces.append(self.driver.scene.indenter_force())
        self.driver.state.F_at_rest = float(np.mean(forces))
        self.driver.state.y_top0 = self.driver.scene.indenter_top_y()
        self.driver.state.t_load = m.time
        self.driver.book_wall_time()   # the hold is the settle's
        self.driver.state.phase = "load"
        self.driver.apply_boundary_conditions()
        m.set_bond_params(check_failure=True)
        m.reset_energy()
        self.driver.recorder.set_reference(m.positions)
        self.driver.recorder.force(0.0, 0.0, self.driver.state.F_at_rest)
        print(f"[settle] at rest after {self.driver.state.settle_time:.3f} s simulated (max node speed "
              f"{self.driver.state.settle_max_speed:.2g} m/s, largest block move {self.driver.state.settle_max_block_move * 1e3:.1f} mm"
              + (f", {self.driver.state.settle_splits} bond points split" if checked else "")
              + f"); indenter force at rest {self.driver.state.F_at_rest:.1f} N/m", flush=True)

    def indenter_held(self):
        """settle_indenter='held': the indenter is held from the first step."""
        return self.driver.params["settle_indenter"] == "held"

    def hold_indenter(self):
        """The indenter's top at zero velocity, where it is now."""
        self.driver.model.prescribe_velocity("indenter_top", direction=(0.0, -1.0),
                                             table=(np.array([0.0, 1.0]), np.zeros(2)))

    def settle_step(self, on):
        """The settle's larger step and back. On: the inertial masses of
        settle_mass_scaling_dt and the same fraction of the stable step as the
        loading's step. Off (at rest): the loading's masses and step again, the
        raises of the larger step dropped and those the rest state needs made
        (engine reset_contact_masses)."""
        m, o = self.driver.model, self.driver.options
        if on:
            fraction = m.dt / m.stable_time_step()["dt"]
            m.set(mass_scaling_dt=o.settle_mass_scaling_dt)
            m.set(dt=fraction * m.stable_time_step()["dt"])
        else:
            m.set(mass_scaling_dt=o.mass_scaling_dt or 0.0)
            m.set(dt=self.driver.params["dt"])
            m.reset_contact_masses()
