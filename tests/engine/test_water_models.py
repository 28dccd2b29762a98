"""The three readings of Table 1's "water: viscous damping constant 2.5e4 Pa s"
(docs/model.md, water drag): linear drag per block, quadratic form drag, and a
viscosity of the block material. Each against its analytic solution."""
import numpy as np
import pytest

from icerubble import engine

from icerubble.parameters import GRAVITY as G, RHO_I, RHO_W


def block(nx, ny, h, origin=(0.0, 0.0), **mat):
    nodes, tri = engine.rectangle_mesh(nx, ny, h, origin=origin)
    m = engine.Model(nodes, tri, np.zeros(len(tri), int), dict(dict(E=1e8, nu=0.3, rho=RHO_I), **mat))
    return m, nodes


# ------------------------------------------------------------ quadratic drag
@pytest.mark.parametrize("direction, width", [
    ((1.0, 0.0), 0.5),                              # edgewise: across V the block is 0.5 m
    ((0.0, -1.0), 1.0),                             # broadside: 1 m
    ((1.0, 1.0), (1.0 + 0.5) / np.sqrt(2.0)),       # 45 deg: extent of the rectangle across V
])
def test_form_drag_of_a_translating_block_is_half_rho_cd_v2_times_its_width_across_v(direction, width):
    """-1/2 rho_w C_d |V| V L per unit width, L the block's width across V."""
    C_d, speed = 1.3, 0.7
    m, nodes = block(4, 2, 0.25)   # 1 m x 0.5 m
    m.set(gravity=False, buoyancy=False, drag=True, drag_model="quadratic", C_d=C_d, y_w=10.0)
    v = speed * np.asarray(direction) / np.hypot(*direction)
    m.set_velocities(np.tile(v, (len(nodes), 1)))
    m.evaluate()
    np.testing.assert_allclose(m.forces("total").sum(axis=0),
                               -0.5 * RHO_W * C_d * speed * v * width, rtol=1e-12)


def test_form_drag_slows_a_block_as_v0_over_1_plus_k_v0_t_over_m():
    """M dV/dt = -k V², k = rho_w C_d L/2: V = V0/(1 + k V0 t/M). The explicit
    update errs by O(dt k V/M) per step relative, ~1e-5 over the run."""
    C_d, v0 = 1.0, 2.0
    m, nodes = block(4, 2, 0.25)
    m.set(gravity=False, buoyancy=False, drag=True, drag_model="quadratic", C_d=C_d, y_w=10.0,
          dt=2e-4)
    m.set_velocities(np.tile([v0, 0.0], (len(nodes), 1)))
    m.step(5000)
    mass, k = RHO_I * 0.5, 0.5 * RHO_W * C_d * 0.5
    expected = v0 / (1.0 + k * v0 * m.time / mass)
    assert expected < 0.5 * v0       # really slowed down
    np.testing.assert_allclose(m.velocities[:, 0], expected, rtol=1e-3)
    e = m.energies()
    assert e["drag"] == pytest.approx(0.5 * mass * v0 ** 2 - e["kinetic"], rel=1e-6)


@pytest.mark.parametrize("law", ["linear", "quadratic"])
def test_a_heavy_block_sinks_at_its_terminal_speed(law):
    """A block denser than water (1500 kg/m³) sinks broadside until drag
    balances its net weight W' = (rho - rho_w) g A: V = W'/c_w (linear) or
    sqrt(2 W'/(rho_w C_d L)) (quadratic, L = 1 m). Time constants: M/c_w =
    0.25 s, V_t/g' = 0.48 s; 4 s leave < 1e-7 of the approach."""
    rho, c_w, C_d = 1500.0, 1500.0, 1.0
    m, nodes = block(4, 1, 0.25, rho=rho)   # 1 m x 0.25 m
    m.set(gravity=True, buoyancy=True, drag=True, drag_model=law, c_w=c_w, C_d=C_d, y_w=100.0)
    m.set(dt=0.5 * m.stable_time_step()["dt"])
    m.step(int(4.0 / m.params["dt"]))
    w_net = (rho - RHO_W) * G * 0.25
    v_t = w_net / c_w if law == "linear" else np.sqrt(2.0 * w_net / (RHO_W * C_d * 1.0))
    assert m.velocities[:, 1].mean() == pytest.approx(-v_t, rel=1e-3)


def test_drag_model_none_and_drag_off_give_no_drag():
    for kw in (dict(drag=True, drag_model="none"), dict(drag=False, drag_model="quadratic")):
        m, nodes = block(4, 2, 0.25)
        m.set(gravity=False, buoyancy=False, y_w=10.0, **kw)
        m.set_velocities(np.tile([1.0, 0.5], (len(nodes), 1)))
        m.evaluate()
        assert np.abs(m.forces("total")).max() < 1e-9


def test_bad_drag_model_and_C_d_are_refused_with_the_valid_values():
    m, _ = block(2, 1, 0.25)
    with pytest.raises(ValueError, match="drag_model.*'linear', 'quadratic', 'none'"):
        m.set(drag_model="Stokes")
    with pytest.raises(ValueError, match="C_d"):
        m.set(C_d=-1.0)
    with pytest.raises(ValueError, match="viscosity"):
        engine.Model(*engine.rectangle_mesh(2, 1, 0.25), np.zeros(4, int),
                   dict(E=1e8, rho=RHO_I, viscosity=-5.0))


# ------------------------------------------------------- material viscosity
def bar_mode(eta, nx=80, h=0.05, periods=8):
    """Fundamental free-free mode of a bar in uniaxial strain (top and bottom
    nodes on rollers): u = a cos(pi x/L). Returns times, end velocity,
    mechanical energy (kinetic + elastic) and the model."""
    L = nx * h
    nodes, tri = engine.rectangle_mesh(nx, 1, h)
    m = engine.Model(nodes, tri, np.zeros(len(tri), int),
                   dict(E=1e8, nu=0.3, rho=RHO_I, viscosity=eta),
                   node_sets={"all": np.arange(len(nodes))})
    m.set(gravity=False)
    m.fix("all", x=False, y=True)
    m.set_velocities(np.column_stack([1e-3 * np.cos(np.pi * nodes[:, 0] / L), np.zeros(len(nodes))]))
    m.set(dt=0.5 * m.stable_time_step()["dt"])
    E, nu = 1e8, 0.3
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    omega = np.pi * np.sqrt(M / RHO_I) / L
    n = int(periods * 2 * np.pi / omega / m.params["dt"])
    end = np.flatnonzero(nodes[:, 0] == 0.0)
    t, v, em = [], [], []
    for _ in range(n):
        m.step(1)
        e = m.energies()
        t.append(m.time)
        v.append(m.velocities[end, 0].mean())
        em.append(e["kinetic"] + e["elastic"])
    return np.array(t), np.array(v), np.array(em), m, M, omega


def test_block_viscosity_damps_a_bar_mode_at_rate_eta_omega2_over_2M():
    """Kelvin-Voigt bar, rho u_tt = M u_xx + eta u_txx: a mode of frequency w
    decays at rate w²eta/(2M) (amplitude), its energy at twice that. In the
    lumped-mass mesh the viscous matrix is eta/M times the stiffness matrix,
    so the same holds with the mesh's own w: measured from the zero crossings,
    within 0.1 % of the continuum pi c/L at 80 elements. The energy ratio over
    whole periods is compared (same phase), within 1 %."""
    eta = 1.8e4    # ~2 % of critical for this mode
    t, v, em, m, M, omega = bar_mode(eta)
    # the damped frequency from the zero crossings of the end velocity
    up = np.flatnonzero((v[:-1] < 0) & (v[1:] >= 0))
    tc = t[up] - v[up] * (t[up + 1] - t[up]) / (v[up + 1] - v[up])
    period = np.mean(np.diff(tc))
    zeta = eta * omega / (2 * M)
    w_h = 2 * np.pi / period / np.sqrt(1 - zeta ** 2)
    assert w_h == pytest.approx(omega, rel=1e-3)
    # energy over whole periods, from the first to the last crossing
    e0, e1 = np.interp(tc[0], t, em), np.interp(tc[-1], t, em)
    rate = -np.log(e1 / e0) / (tc[-1] - tc[0])
    assert rate == pytest.approx(eta * w_h ** 2 / M, rel=1e-2)
    # the lost energy is booked as damping: the balance closes
    e = m.energies()
    assert e["damping"] > 0.5 * em[0]
    assert abs(e["residual"]) < 1e-3 * e["damping"]


def test_block_viscosity_does_not_damp_a_spinning_block():
    """The viscous stress uses the rate of Green strain: a rigid spin at 3
    rad/s is no strain rate (objective). A rate with the spin in it would
    dissipate eta w² A per unit time; what is dissipated is only the small
    centrifugal stretching vibration (the block starts unstretched), below
    1e-6 of that."""
    m, nodes = block(4, 2, 0.25, viscosity=2.5e4)
    m.set(gravity=False)
    c = nodes.mean(axis=0)
    w = 3.0
    m.set_velocities(np.column_stack([-w * (nodes[:, 1] - c[1]), w * (nodes[:, 0] - c[0])]))
    m.set(dt=0.5 * m.stable_time_step()["dt"])
    m.step(2000)
    e = m.energies()
    spin_rate_dissipation = 2.5e4 * w ** 2 * 0.5 * m.time
    assert 0.0 <= e["damping"] < 1e-6 * spin_rate_dissipation


def test_block_viscosity_lowers_the_stable_step_as_a_damped_element():
    """The element limit with damping ratio xi is (2/w)(sqrt(1+xi²) - xi);
    the viscosity enters through eta/(2 mu), the largest ratio of any mode."""
    dts = []
    for eta in (0.0, 2.5e5):
        m, _ = block(4, 2, 0.25, viscosity=eta)
        s = m.stable_time_step()
        dts.append((s["dt_element"], s["damping_ratio"]))
    (dt0, xi0), (dt1, xi1) = dts
    assert xi0 == 0.0 and xi1 > 0.0
    assert dt1 == pytest.approx(dt0 * (np.sqrt(1 + xi1 ** 2) - xi1), rel=1e-12)
