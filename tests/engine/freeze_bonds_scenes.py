"""Small bonded scenes shared by the freeze-bond tests (tests/engine/test_freeze_bonds_*.py)."""
import numpy as np

from icerubble import engine
from icerubble.geometry.bond_points import find_bond_points

ICE = dict(E=2e9, nu=0.3, rho=920.0)


def bonded(nodes, tri, body, sigma_cr, tau_cr, G, damping=0.0, **bond_kw):
    """A model of the mesh with every inter-body edge bonded at uniform
    strength (bottom_fraction=1: no depth scaling)."""
    m = engine.Model(nodes, tri, body, dict(ICE, damping=damping))
    bp = find_bond_points(nodes, tri, body, keel_top_y=nodes[:, 1].max(), keel_depth=1.0,
                          sigma_cr=sigma_cr, tau_cr=tau_cr, G=G, bottom_fraction=1.0)
    m.set(gravity=False, penalty=1e9)
    m.set_bond_points(bp, **bond_kw)
    return m, bp


def two_block_bar(nx=20, ny=4, h=0.05, **kw):
    """Bar [0, nx h] x [0, ny h] of two blocks joined across x = nx h / 2."""
    nodes, tri = engine.rectangle_mesh(nx, ny, h)
    c = nodes[tri].mean(axis=1)
    body = (c[:, 0] > 0.5 * nx * h).astype(np.int32)
    m, bp = bonded(nodes, tri, body, **kw)
    return m, bp, nodes


def diagonal_square(n=8, h=0.05, **kw):
    """Square [0, n h]^2 of two blocks joined along the diagonal y = x
    (rectangle_mesh cuts every cell along it): normal (1, -1)/sqrt(2) from the
    upper-left block 0 to the lower-right block 1."""
    nodes, tri = engine.rectangle_mesh(n, n, h)
    c = nodes[tri].mean(axis=1)
    body = (c[:, 0] > c[:, 1]).astype(np.int32)
    m, bp = bonded(nodes, tri, body, **kw)
    return m, bp, nodes


def elastic_force(m, name, component):
    """Elastic element force the nodes of set ``name`` feel, summed [N/m]: at a
    held node, what the body pulls on its support with."""
    f = m.forces("internal") - m.forces("viscous")
    return f[m.node_sets[name], component].sum()


def pull_bar(direction="paper", sigma_cr=1e4, tau_cr=5e4, G=1.0, v_slow=1e-4, v_fast=4e-3,
             t_fast=0.07, damping=0.0, **kw):
    """The two-block bar, left end held in x (one node also in y), right end
    pulled in x: a smooth start to v_slow (0.02 s), v_slow past the peak, then
    v_fast from t_fast to t_fast + 0.01 s so the softening does not take many
    steps. Returns model, bond points, nodes, height H."""
    m, bp, nodes = two_block_bar(sigma_cr=sigma_cr, tau_cr=tau_cr, G=G, damping=damping,
                                 direction=direction, **kw)
    L, H = nodes[:, 0].max(), nodes[:, 1].max()
    m.add_node_set("left", np.flatnonzero(nodes[:, 0] == 0.0))
    m.add_node_set("right", np.flatnonzero(nodes[:, 0] == L))
    m.add_node_set("pin", [0])
    m.fix("left", x=True, y=False)
    m.fix("pin", x=False, y=True)
    m.prescribe_velocity("right", (1, 0), y=False,
                         table=([0.0, 0.02, t_fast, t_fast + 0.01], [0.0, v_slow, v_slow, v_fast]))
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    return m, bp, nodes, H


def body_nodes(m, b):
    """Ids of the nodes that triangles of body b use (split copies included)."""
    return np.unique(np.asarray(m.triangles)[np.asarray(m.body) == b])


def loaded_diagonal_square(load, v, n=8, h=0.05, ramp=0.01, sigma_cr=1e4, tau_cr=5e4, G=1.0,
                           **kw):
    """The diagonal square under a uniform stress that CST represents exactly:
    'tension' / 'compression': uniaxial sigma_xx (left edge held in x, corner
    (0, 0) also in y, right edge driven in +x / -x); 'shear': sigma_xx = -sigma_yy
    (rollers: left x, bottom y held; right driven +x, top -y), i.e. pure shear
    on the diagonal. Speed v after a linear ramp of ``ramp`` seconds."""
    m, bp, nodes = diagonal_square(n=n, h=h, sigma_cr=sigma_cr, tau_cr=tau_cr, G=G, **kw)
    W = n * h
    on = lambda c, x: np.flatnonzero(np.isclose(nodes[:, c], x))
    table = ([0.0, ramp], [0.0, v])
    m.add_node_set("left", on(0, 0.0))
    m.add_node_set("right", on(0, W))
    m.fix("left", x=True, y=False)
    if load == "shear":
        m.add_node_set("bottom", on(1, 0.0))
        m.add_node_set("top", on(1, W))
        m.fix("bottom", x=False, y=True)
        m.prescribe_velocity("right", (1, 0), table=table, y=False)
        m.prescribe_velocity("top", (0, -1), table=table, x=False)
    else:
        m.add_node_set("pin", [0])
        m.fix("pin", x=False, y=True)
        m.prescribe_velocity("right", (1 if load == "tension" else -1, 0), table=table, y=False)
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    return m, bp, nodes, W


def step_until_split(m, limit):
    """Step until some bond point splits; returns the elastic force the right
    edge pulls with (x) just before the splitting step, and after it."""
    before = None
    while m.bonds.counts["split"] == 0:
        if m.time > limit:
            raise AssertionError(f"no bond point split by t = {limit} s")
        before = -elastic_force(m, "right", 0) if m.step_count else 0.0
        m.step(1)
    return before
