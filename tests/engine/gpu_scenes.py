"""The scenes the GPU backend is checked on (tests/engine/test_gpu_backend.py,
tools/gpu_check.py): three floating blocks straddling the water line, with
damping, viscosity and a drag model, their nodes nudged and given random
velocities, so every branch of the body-force stage's kernels runs (partly
submerged triangles, damping, each drag model).

`on_gpu_or_emulation` marks a test of the backend: it runs on the GPU where
one is visible, else on the backend's CPU emulation where the build has it
(docs/gpu.md, "The emulation"), else it is skipped with the reason."""
import functools
import os

import numpy as np
import pytest

from icerubble import engine
from icerubble.engine import gpu


def on_gpu_or_emulation(test):
    """`test` run on the GPU, else on the CPU emulation (EMULATION_ENV set
    for it alone), else skipped saying why."""
    emulate = not gpu.available() and gpu.emulation_built()

    @pytest.mark.skipif(not (gpu.available() or emulate), reason=f"GPU backend: {gpu.why_unavailable()}")
    @functools.wraps(test)
    def run(*args, **kwargs):
        if not emulate:
            return test(*args, **kwargs)
        before = os.environ.get(gpu.EMULATION_ENV)
        os.environ[gpu.EMULATION_ENV] = "1"
        try:
            return test(*args, **kwargs)
        finally:
            if before is None:
                del os.environ[gpu.EMULATION_ENV]
            else:
                os.environ[gpu.EMULATION_ENV] = before
    return run


def floating_blocks(rng, drag_model):
    """Three 0.6 m x 0.3 m blocks of 0.05 m cells across the water line y = 0."""
    nodes, tris, body = [], [], []
    for b, (x0, y0) in enumerate([(0.0, -0.2), (0.7, -0.25), (0.2, -0.6)]):
        n, t = engine.rectangle_mesh(12, 6, 0.05, origin=(x0, y0))
        tris.append(t + sum(len(p) for p in nodes))
        nodes.append(n)
        body += [b] * len(t)
    nodes = np.vstack(nodes)
    m = engine.Model(nodes, np.vstack(tris), np.array(body),
                     materials={b: dict(E=5e9, nu=0.3, rho=920.0, damping=1e-5, viscosity=2e3)
                                for b in range(3)})
    m.set(buoyancy=True, drag=drag_model != "none", drag_model=drag_model, y_w=0.0, dt_fraction=0.8)
    m.set_positions(nodes + rng.uniform(-0.004, 0.004, nodes.shape))
    m.set_velocities(rng.normal(0.0, 0.05, nodes.shape))
    return m



def driven_block(rng, drag_model, nx=16, ny=8, h=0.05):
    """One 0.8 m x 0.4 m block of 0.05 m cells across the water line y = 0
    (damping, viscosity, `drag_model`), its nodes nudged and moving at random:
    its left side held in x ('left') and its top pushed down at a speed that
    rises smoothly to 5 mm/s over 2 ms ('top'), so whole steps run every
    stage of a step without contact: elements, water, both kinds of boundary
    condition, the update and the ledger."""
    nodes, tris = engine.rectangle_mesh(nx, ny, h, origin=(0.0, -0.25))
    m = engine.Model(nodes, tris, np.zeros(len(tris), dtype=np.int32),
                     materials={0: dict(E=5e9, nu=0.3, rho=920.0, damping=1e-5, viscosity=2e3)})
    m.set(buoyancy=True, drag=drag_model != "none", drag_model=drag_model, y_w=0.0, dt_fraction=0.8)
    m.set_positions(nodes + rng.uniform(-0.002, 0.002, nodes.shape))
    m.set_velocities(rng.normal(0.0, 0.02, nodes.shape))
    ids = np.arange(len(nodes))
    m.add_node_set("left", ids[ids % (nx + 1) == 0])
    m.add_node_set("top", ids[ids // (nx + 1) == ny])
    m.fix("left", y=False)
    m.prescribe_velocity("top", direction=(0.0, -1.0), v_final=5e-3, ramp_time=2e-3, x=False)
    return m


def sliding_block(rng, speed=3.0):
    """A 0.3 m x 0.15 m block set 1 um above a 1 m x 0.2 m slab whose bottom
    is held, sliding along it at `speed` [m/s] under gravity (no water), its
    nodes nudged: it lands within a millisecond and slides on, its touching
    pairs sticking and slipping, and within a few thousand steps its nodes
    move past the candidate list's skin (5 mm on these 0.05 m cells), so the
    list is rebuilt."""
    h = 0.05
    a_nodes, a_tri = engine.rectangle_mesh(20, 4, h, origin=(0.0, 0.0))
    b_nodes, b_tri = engine.rectangle_mesh(6, 3, h, origin=(0.1, 0.2 + 1e-6))
    nodes = np.vstack((a_nodes, b_nodes))
    tri = np.vstack((a_tri, b_tri + len(a_nodes)))
    body = np.repeat([0, 1], [len(a_tri), len(b_tri)])
    m = engine.Model(nodes, tri, body, materials={b: dict(E=5e9, nu=0.3, rho=920.0, damping=1e-5) for b in (0, 1)})
    m.set(gravity=True, water=False, mu=0.3, dt_fraction=0.8)
    m.set_positions(nodes + rng.uniform(-4e-7, 4e-7, nodes.shape))
    v = np.zeros(nodes.shape)
    v[len(a_nodes):, 0] = speed
    m.set_velocities(v + rng.normal(0.0, 1e-4, nodes.shape))
    ids = np.arange(len(a_nodes))
    m.add_node_set("slab_bottom", ids[ids // 21 == 0])
    m.fix("slab_bottom")
    return m

def pressed_blocks(rng):
    """A 1.2 m x 0.3 m block on a wider one, 20 um into it, tilted and nudged
    so that every contact pair is cut differently: many touching pairs."""
    n0, t0 = engine.rectangle_mesh(24, 6, 0.05, origin=(0.0, -0.3))
    n1, t1 = engine.rectangle_mesh(24, 6, 0.05, origin=(0.3, -2e-5))
    nodes = np.vstack([n0, n1])
    tris = np.vstack([t0, t1 + len(n0)])
    body = np.array([0] * len(t0) + [1] * len(t1))
    m = engine.Model(nodes, tris, body, materials={b: dict(E=5e9, nu=0.3, rho=920.0) for b in range(2)})
    m.set(penalty=2e11, mu=0.3, dt_fraction=0.8)
    tilt = 1e-5 * (n1[:, 0] - 0.9)  # a 10 urad tilt of the top block
    xy = nodes.copy()
    xy[len(n0):, 1] += tilt
    m.set_positions(xy + rng.uniform(-2e-6, 2e-6, nodes.shape))
    return m


def bonded_square(rng):
    """Two blocks bonded along a diagonal (tests/engine/freeze_bonds_scenes.py),
    their nodes nudged so that the stresses differ from point to point and
    some bond points reach eq 5 and others do not."""
    from tests.engine.freeze_bonds_scenes import diagonal_square
    m, _, nodes = diagonal_square(sigma_cr=6e4, tau_cr=1.2e5, G=1.0)
    m.set(dt_fraction=0.8)
    m.set_positions(nodes + rng.uniform(-2e-6, 2e-6, nodes.shape))
    return m


def opened_square(rng, direction="paper"):
    """The bonded square (bonded_square) stepped with its bond check on: the
    points its nudge put past eq 5 split and open. Yields the model just
    after the first split (rigid phase), with opened pairs softening 50 and
    150 steps later, and, for a square with a tiny fracture energy, at the
    first state from which the cohesive law fails a pair (its failure
    branch). direction: eq 11 as printed ('paper') or 'work_conjugate'."""
    from icerubble import _engine
    from tests.engine.freeze_bonds_scenes import diagonal_square
    seed = int(rng.integers(1 << 30))
    for G in (1.0, 1e-4):
        m, _, nodes = diagonal_square(sigma_cr=6e4, tau_cr=1.2e5, G=G, direction=direction)
        m.set(dt_fraction=0.8)
        m.set_positions(nodes + np.random.default_rng(seed).uniform(-2e-6, 2e-6, nodes.shape))
        if G == 1.0:
            for n in (1, 50, 100):
                m.step(n)
                yield m
            continue
        for _ in range(1000):
            m.step(1)
            m._m.evaluate_before_cohesive()
            if np.any(_engine.cohesive_fields(m._m)["failed"]):
                yield m
                return
        raise AssertionError("no opened pair of the square failed within 1000 steps")


def rubbing_blocks(rng):
    """The pressed blocks (pressed_blocks) given random velocities of a few
    mm/s and stepped once: touching pairs that stick and slip, coupled
    through shared nodes, with a warm start from the step before (the
    penalty pushes the blocks apart within a few steps)."""
    m = pressed_blocks(rng)
    m.set_velocities(rng.normal(0.0, 3e-3, m.positions.shape))
    m.step(1)
    return m


def landing_block_and_a_flyer(rng, speed=20.0):
    """The sliding block (sliding_block) let down at rest onto its slab,
    with a third block flying past 8 mm above it at `speed` [m/s], touching
    nothing: the flyer's nodes move past the candidate list's skin every few
    hundred steps, so the list is rebuilt, some times while the landed
    block's pairs stick, and the flyer's candidates with the block change
    from one list to the next (the candidates' count and arrays change). The
    friction warm start the sticking pairs carry across a rebuild changes
    their forces (a sliding pair's force is its limit from any start)."""
    h = 0.05
    a_nodes, a_tri = engine.rectangle_mesh(20, 4, h, origin=(0.0, 0.0))
    b_nodes, b_tri = engine.rectangle_mesh(6, 3, h, origin=(0.1, 0.2 + 1e-6))
    c_nodes, c_tri = engine.rectangle_mesh(4, 2, h, origin=(0.0, 0.358))
    nodes = np.vstack((a_nodes, b_nodes, c_nodes))
    tri = np.vstack((a_tri, b_tri + len(a_nodes), c_tri + len(a_nodes) + len(b_nodes)))
    body = np.repeat([0, 1, 2], [len(a_tri), len(b_tri), len(c_tri)])
    m = engine.Model(nodes, tri, body,
                     materials={b: dict(E=5e9, nu=0.3, rho=920.0, damping=1e-5) for b in (0, 1, 2)})
    m.set(gravity=True, water=False, mu=0.3, dt_fraction=0.8)
    m.set_positions(nodes + rng.uniform(-4e-7, 4e-7, nodes.shape))
    v = rng.normal(0.0, 1e-4, nodes.shape)
    v[len(a_nodes) + len(b_nodes):, 0] += speed
    m.set_velocities(v)
    ids = np.arange(len(a_nodes))
    m.add_node_set("slab_bottom", ids[ids // 21 == 0])
    m.fix("slab_bottom")
    return m


def scattered_blocks(rng, near, far=0, spread=3.0, far_spread=2000.0):
    """`near` blocks of two cells, of random sizes and turns, strewn over a
    `spread` m square (overlapping freely: the search does not care), and
    `far` more over a `far_spread` m one, whose extent makes the search
    coarsen its grid to the cell cap."""
    nodes, tris, body = [], [], []
    for b in range(near + far):
        h = rng.uniform(0.03, 0.2)
        n, t = engine.rectangle_mesh(2, 1, h)
        a = rng.uniform(0.0, 2.0 * np.pi)
        n = n @ np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])
        tris.append(t + sum(len(k) for k in nodes))
        nodes.append(n + rng.uniform(0.0, spread if b < near else far_spread, 2))
        body += [b] * len(t)
    return engine.Model(np.vstack(nodes), np.vstack(tris), np.array(body),
                        materials={b: dict(E=5e9, nu=0.3, rho=920.0) for b in range(near + far)})


def pulled_bar(direction="paper"):
    """Two blocks bonded across the middle of a bar, one end held, the other
    pulled (tests/engine/freeze_bonds_scenes.py pull_bar): in 14,000 steps
    its five bond points split (steps the model takes itself), open in the
    rigid phase, soften and fail (the GPU's steps, the opened pairs made
    again after them)."""
    from tests.engine.freeze_bonds_scenes import pull_bar
    return pull_bar(direction=direction)[0]


def shaken_bar(direction="paper"):
    """pulled_bar with every node set moving at random (0.3 m/s, no
    damping): its points split within a few steps of one another while the
    bar rings, so the GPU's batches halt on splits amid steps whose
    screening flags change, and a split step's neighbour search (before the
    split, on the CPU) is followed by one on the split mesh."""
    m = pulled_bar(direction)
    m.set_velocities(np.random.default_rng(3).normal(0.0, 0.3, m.positions.shape))
    return m


def sheared_square(direction="paper"):
    """Two blocks bonded along the diagonal of a square in pure shear
    (freeze_bonds_scenes.py loaded_diagonal_square): within 1,000 steps its
    nine bond points split and seven pairs fail, under compression across
    the bond, so the split pairs' crack closure pushes too."""
    from tests.engine.freeze_bonds_scenes import loaded_diagonal_square
    return loaded_diagonal_square("shear", 0.02, G=0.2, direction=direction)[0]
