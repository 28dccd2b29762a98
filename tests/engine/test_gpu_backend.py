"""The GPU backend's body-force stage (docs/gpu.md) gives the CPU's bits:
the same per-triangle, per-body and per-node functions, the same order in
every per-node sum. Where no GPU is visible the comparisons run on the
backend's CPU emulation (the build without a CUDA toolkit has it), and the
backend says why it cannot run without it."""
import re

import numpy as np
import pytest

from icerubble import _engine
from icerubble.engine import gpu
from tests.engine.gpu_scenes import (bonded_square, driven_block, floating_blocks, landing_block_and_a_flyer,
                                     on_gpu_or_emulation, opened_square, pressed_blocks, pulled_bar, rubbing_blocks,
                                     scattered_blocks, shaken_bar, sheared_square, sliding_block)


def test_the_backend_says_why_it_cannot_run():
    if gpu.available():
        pytest.skip("a GPU is visible here")
    m = floating_blocks(np.random.default_rng(0), "linear")
    with pytest.raises(RuntimeError, match=re.escape("GPU backend cannot run: " + gpu.why_unavailable())):
        gpu.BodyForces(m)
    with pytest.raises(RuntimeError, match=re.escape("GPU backend cannot run: " + gpu.why_unavailable())):
        gpu.Steps(driven_block(np.random.default_rng(0), "linear"))


@on_gpu_or_emulation
@pytest.mark.parametrize("drag_model", ["linear", "quadratic", "none"])
def test_gpu_body_forces_are_the_cpus_bits(drag_model):
    m = floating_blocks(np.random.default_rng(7), drag_model)
    cmp = gpu.compare(m)
    assert {k: cmp[k][0] for k in gpu.EXACT_FIELDS} == {k: 0 for k in gpu.EXACT_FIELDS}
    # the terms are the CPU's; only the order of their sums differs
    for k in gpu.SUMMED_FIELDS + ("elastic_energy",):
        assert cmp[k][1] <= gpu.ROUND_OFF, (k, cmp[k])
    if drag_model != "quadratic":  # no per-body sum: the CPU's bits
        assert cmp["drag_k"][0] == 0


@on_gpu_or_emulation
def test_a_second_gpu_run_gives_the_same_bits():
    stage = gpu.BodyForces(floating_blocks(np.random.default_rng(3), "quadratic"))
    stage.run()
    a = stage.fields()
    stage.run()
    b = stage.fields()
    for k in gpu.FIELDS:
        assert np.array_equal(np.asarray(a[k]).view(np.uint64), np.asarray(b[k]).view(np.uint64)), k
    assert a["elastic_energy"] == b["elastic_energy"]


@on_gpu_or_emulation
@pytest.mark.parametrize("drag_model", ["linear", "quadratic"])
def test_the_gpu_update_is_the_cpus_step(drag_model):
    m = floating_blocks(np.random.default_rng(11), drag_model)
    m.step(2)
    cmp = gpu.compare_update(m)
    assert {k: cmp[k][0] for k in ("x", "y", "vx", "vy")} == {"x": 0, "y": 0, "vx": 0, "vy": 0}
    assert cmp["ledger"] <= gpu.ROUND_OFF


@on_gpu_or_emulation
def test_the_gpu_normal_contact_is_the_cpus():
    cmp = gpu.compare_contact(pressed_blocks(np.random.default_rng(5)))
    assert cmp["touching"][0] > 10 and cmp["touching"][0] == cmp["touching"][1]
    assert (cmp["f_con_x"][0], cmp["f_con_y"][0]) == (0, 0)
    assert cmp["energy_rel"] <= gpu.ROUND_OFF


@on_gpu_or_emulation
@pytest.mark.parametrize("seed", [1, 2, 4])
def test_the_gpu_bond_check_gives_the_cpus_plan(seed):
    cmp = gpu.compare_bond_check(bonded_square(np.random.default_rng(seed)))
    assert cmp["plan"][0] > 0 and cmp["same_plan"]
    assert (cmp["ratio"], cmp["tn"], cmp["tt"]) == (0, 0, 0)


@on_gpu_or_emulation
@pytest.mark.parametrize("direction", ["paper", "work_conjugate"])
def test_the_gpu_cohesive_forces_are_the_cpus(direction):
    """Rigid phase, softening and failure of the square's opened pairs: per
    pair and per node the CPU's bits, the energy sums to round-off."""
    for m in opened_square(np.random.default_rng(3), direction=direction):
        cmp = gpu.compare_cohesive(m)
        assert cmp["pairs"] > 0 and cmp["ok"], cmp


@on_gpu_or_emulation
@pytest.mark.parametrize("seed", [3, 8])
@pytest.mark.parametrize("earlier_list,shared_nodes", [(None, None), (1, None), (0, None), (None, 0)])
def test_the_gpu_friction_is_the_cpus(seed, earlier_list, shared_nodes):
    # earlier_list: the colouring's list of a pair's earlier neighbours, as
    # built (None), or so short that some (1) or all (0) pairs walk their nodes;
    # shared_nodes 0: the sweeps read the nodes' arrays, not shared memory
    cmp = gpu.compare_friction(rubbing_blocks(np.random.default_rng(seed)), earlier_list=earlier_list,
                               shared_nodes=shared_nodes)
    # ~90 pairs, held by the sweeps' lanes (up to four a lane: more than one
    # on the emulation's 32 lanes), their nodes in shared memory unless told not to
    assert (cmp["local_nodes"] > 10) if shared_nodes is None else (cmp["local_nodes"] == -1), cmp
    assert cmp["pairs"][0] > 10 and cmp["pairs"][0] == cmp["pairs"][1]   # the GPU finds the CPU's touching pairs
    assert cmp["colours"][0] > 1 and cmp["colours"][0] == cmp["colours"][1]
    assert cmp["colour"] == 0  # the GPU's parallel colouring is the CPU's greedy one
    assert (cmp["lambda"][0], cmp["f_x"][0], cmp["f_y"][0]) == (0, 0, 0)
    assert cmp["power_rel"] <= gpu.ROUND_OFF
    # a second run with the same touching pairs keeps the colouring, same bits
    assert cmp["again"] and cmp["colourings"] == 1, cmp


@on_gpu_or_emulation
def test_the_gpu_friction_of_more_pairs_than_shared_memory_holds_is_the_cpus():
    # ~10,800 touching pairs: more than the colouring keeps in shared memory
    # (kSharedSlots, cuda/friction.cu), so its colours are kept in global memory
    from tests.engine.test_contact_threads import pressed_wall
    cmp = gpu.compare_friction(pressed_wall(1))
    assert cmp["pairs"][0] > 8192 and cmp["pairs"][0] == cmp["pairs"][1], cmp["pairs"]
    assert cmp["colours"][0] == cmp["colours"][1] and cmp["colour"] == 0
    assert (cmp["lambda"][0], cmp["f_x"][0], cmp["f_y"][0]) == (0, 0, 0)
    assert cmp["power_rel"] <= gpu.ROUND_OFF
    assert cmp["again"] and cmp["colourings"] == 1, cmp
    assert cmp["local_nodes"] == -1, cmp  # more pairs than the sweeps' block holds: the nodes' arrays


@on_gpu_or_emulation
def test_the_gpu_friction_of_pairs_held_in_the_sweeps_lanes_is_the_cpus():
    # a block landed on a slab: ~20 touching pairs, each held by a lane of the
    # sweeps' block through every pass (HeldPair: one a lane here, on the
    # emulation's 32 lanes as on a GPU's 1,024), their nodes' velocities and
    # inverse masses in shared memory; then allowed one node fewer than they
    # have, so the held pairs read the nodes' arrays
    model = landing_block_and_a_flyer(np.random.default_rng(3))
    model.step(1000)
    cmp = gpu.compare_friction(model)
    n = cmp["local_nodes"]
    assert 0 < cmp["pairs"][0] <= 32 and n > 0 and cmp["ok"], cmp
    fewer = gpu.compare_friction(model, shared_nodes=n - 1)
    assert fewer["local_nodes"] == -1 and fewer["ok"], fewer


@on_gpu_or_emulation
def test_a_friction_list_length_out_of_range_is_refused():
    stage = gpu.Friction(rubbing_blocks(np.random.default_rng(3)))
    with pytest.raises(ValueError, match="earlier_list=17: valid values are 0 to 16"):
        stage._d.set_earlier_list(17)
    with pytest.raises(ValueError, match=r"shared_nodes=-1: valid values are 0 to \d+"):
        stage._d.set_shared_nodes(-1)


@on_gpu_or_emulation
@pytest.mark.parametrize("drag_model", ["linear", "none"])
def test_whole_gpu_steps_are_the_cpus_steps(drag_model):
    # 300 steps: the ramp of the driven top and past it; every per-node and
    # per-triangle value is the CPU's arithmetic, so the trajectory is the
    # CPU's bits (quadratic drag sums each body's terms in another order:
    # tools/gpu_check.py reports it)
    cmp = gpu.compare_steps(lambda: driven_block(np.random.default_rng(5), drag_model), 300, nodes="top")
    assert {k: cmp[k][0] for k in ("x", "y", "vx", "vy")} == {k: 0 for k in ("x", "y", "vx", "vy")}, cmp
    assert cmp["ledger"] <= gpu.ROUND_OFF and cmp["reaction"] <= gpu.ROUND_OFF and cmp["time"], cmp


@on_gpu_or_emulation
def test_whole_gpu_steps_with_contact_and_friction_are_the_cpus_steps():
    # 4,000 steps of a block sliding on a slab: normal contact and friction on
    # the GPU, the candidate list rebuilt by the model's broad phase at the
    # GPU's positions and put into the stages in place, no step of the model's
    cmp = gpu.compare_steps(lambda: sliding_block(np.random.default_rng(9)), 4000, nodes="slab_bottom")
    assert cmp["list_rebuilds"] >= 1 and cmp["host_steps"] == 0, cmp  # the block moved past the skin
    assert {k: cmp[k][0] for k in ("x", "y", "vx", "vy")} == {k: 0 for k in ("x", "y", "vx", "vy")}, cmp
    assert cmp["ledger"] <= gpu.ROUND_OFF and cmp["reaction"] <= gpu.ROUND_OFF and cmp["time"], cmp


@on_gpu_or_emulation
def test_the_friction_warm_start_crosses_a_list_rebuild_on_the_gpu():
    # a block come to rest on a slab, its pairs sticking, while a third block
    # flies past above: the list is rebuilt every few hundred steps, some of
    # them while the pairs stick, whose forces then depend on the warm start
    # carried over by key (dropping it at the rebuild fails this test)
    cmp = gpu.compare_steps(lambda: landing_block_and_a_flyer(np.random.default_rng(4)), 4000, nodes="slab_bottom")
    assert cmp["list_rebuilds"] >= 5 and cmp["host_steps"] == 0, cmp
    # the resting block's touching pairs stay for many steps, and the colouring
    # with them: coloured again after a change of them or a rebuild only
    assert cmp["list_rebuilds"] < cmp["colourings"] < 4000 // 4, cmp
    # rebuilt where the CPU rebuilds it (its first list is the GPU's starting one)
    assert cmp["list_rebuilds"] == cmp["cpu_list_builds"] - 1, cmp
    # each rebuild's graph captured again; the launches stay the same, so on
    # the emulation (which updates where they match) it is updated in place
    assert cmp["graph_instantiations"] + cmp["graph_updates"] >= cmp["list_rebuilds"] + 1, cmp
    if gpu.emulated():
        assert cmp["graph_instantiations"] == 1, cmp
    assert {k: cmp[k][0] for k in ("x", "y", "vx", "vy")} == {k: 0 for k in ("x", "y", "vx", "vy")}, cmp
    assert cmp["ledger"] <= gpu.ROUND_OFF and cmp["reaction"] <= gpu.ROUND_OFF and cmp["time"], cmp


@on_gpu_or_emulation
def test_whole_gpu_steps_with_a_bounded_contact_reach_are_the_cpus_steps():
    # the presets' bounded contact step (contact_reach): the GPU tests in the
    # model's turns whether a node moved past reach/2, and the model re-bounds
    # the step (here its origins move; no mass needs raising), the stages
    # made again with the step's reactions
    def make():
        m = sliding_block(np.random.default_rng(9))
        m.set(contact_reach=0.001)
        return m
    cmp = gpu.compare_steps(make, 4000, nodes="slab_bottom")
    assert cmp["remakes"] > 2 * cmp["host_steps"], cmp  # re-bound, beyond the list's rebuilds
    assert cmp["ok"], cmp


@on_gpu_or_emulation
def test_a_mass_raise_in_a_gpu_re_bound_is_booked_as_on_the_cpu():
    # test_contact_reach.py's approach with mass scaling, taken on the CPU to
    # just before its first re-bound whose step needs a raise: the GPU's
    # re-bound raises the node the CPU raises, and the kinetic energy the
    # raise takes is in the GPU run's ledger (damping), as in the CPU's
    from tests.engine.test_contact_reach import towards_with_mass_scaling

    def make():
        m, _ = towards_with_mass_scaling()
        m.step(180000)   # the first raise is within the next 6,000 steps
        assert m._m.raised_nodes() == 0
        return m
    cmp = gpu.compare_steps(make, 10000)
    assert cmp["remakes"] >= 1 and cmp["host_steps"] == 0, cmp  # re-bound on the GPU's turn
    assert cmp["ok"], cmp


@on_gpu_or_emulation
@pytest.mark.parametrize("direction", ["paper", "work_conjugate"])
def test_whole_gpu_steps_of_a_bonded_bar_split_and_fail_as_the_cpus(direction):
    # its points split in steps the model takes; their pairs soften and fail
    # in the GPU's steps: the state, the bonds' records and history the CPU's
    # bits; a failed pair stays in the GPU's list, passed over, and nothing
    # is made again for it (remade only after the splits' steps)
    cmp = gpu.compare_steps(lambda: pulled_bar(direction), 14000, nodes="right")
    assert cmp["bond_counts"][0] == (5, 5), cmp  # every point split, every pair failed
    assert cmp["host_steps"] >= 1 and cmp["remakes"] == cmp["host_steps"] and cmp["ok"], cmp


@on_gpu_or_emulation
def test_stages_made_again_take_their_memory_from_the_cache():
    # a host step (a split) makes every stage again: ~150 arrays on the paper
    # mesh, whose memory is the blocks the old stages gave back, not fresh
    # cudaMalloc'd memory (a wait for the device and a mapping each)
    m = pulled_bar()
    gpu.Steps(m)  # made, then gone: its blocks back in the cache
    before = gpu.memory_counts()
    gpu.Steps(m)
    after = gpu.memory_counts()
    assert after["allocations"] == before["allocations"], (before, after)
    assert after["reuses"] > before["reuses"] and after["waits"] >= 1, (before, after)


@on_gpu_or_emulation
def test_a_block_size_class_holds_a_request_and_wastes_at_most_an_eighth():
    classes = [_engine.device_size_class(b) for b in range(1, 1 << 16, 37)]
    for b, c in zip(range(1, 1 << 16, 37), classes):
        assert c >= b and c % 256 == 0 and (c <= 4096 or c <= b * 9 // 8 + 1), (b, c)
    assert classes == sorted(classes)


@on_gpu_or_emulation
def test_whole_gpu_steps_of_a_shaken_bar_are_the_cpus():
    # splits amid ringing: the stages made after a split step start from the
    # list the CPU's next step searches on the split mesh, and a batch halted
    # by a split keeps the screening flags of the steps it ran (checks equal)
    cmp = gpu.compare_steps(shaken_bar, 14000, nodes="right")
    assert cmp["bond_counts"][0] == (5, 5) and cmp["host_steps"] >= 1, cmp
    assert cmp["ok"], cmp


@on_gpu_or_emulation
def test_whole_gpu_steps_of_a_sheared_square_are_the_cpus():
    # failures in shear, and the split pairs' crack closure under compression
    # (the failed pairs' too, from the GPU's list of opened ones)
    cmp = gpu.compare_steps(sheared_square, 3000, nodes="top")
    assert cmp["bond_counts"][0][1] > 0 and cmp["remakes"] == cmp["host_steps"] and cmp["ok"], cmp


@on_gpu_or_emulation
def test_the_gpu_step_says_what_it_does_not_run_yet():
    m = driven_block(np.random.default_rng(0), "linear")
    m.set(sleeping=True)
    with pytest.raises(ValueError, match="does not run the sleeping far field"):
        gpu.Steps(m)


@on_gpu_or_emulation
@pytest.mark.parametrize("far", [0, 12])
def test_the_gpu_finds_the_cpus_contact_candidates(far):
    # 300 blocks strewn over 3 m (and 12 more over 2 km: the grid coarsened
    # to its cap, many triangles a cell): the GPU's search, laid out, is the
    # CPU's, every array (nodes, keys, each node's entries) and the skin
    cmp = gpu.compare_broad_phase(scattered_blocks(np.random.default_rng(7), 300, far))
    assert cmp["same"] and cmp["candidates"][0] > 1000, cmp

