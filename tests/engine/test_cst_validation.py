"""Bad input raises ValueError naming the parameter and its valid range,
before any work starts."""
import numpy as np
import pytest

from icerubble import engine

MAT = dict(E=1e9, nu=0.3, rho=900.0)


@pytest.fixture
def mesh():
    return engine.rectangle_mesh(3, 2, 0.5)


def model(mesh, **mat):
    nodes, tri = mesh
    return engine.Model(nodes, tri, np.zeros(len(tri), int), dict(MAT, **mat))


@pytest.mark.parametrize("key, value, words", [
    ("E", 0.0, ["E", "> 0"]),
    ("E", -1e9, ["E", "> 0"]),
    ("E", np.nan, ["E", "> 0"]),
    ("nu", 0.5, ["nu", "[0, 0.5)"]),
    ("nu", -0.1, ["nu", "[0, 0.5)"]),
    ("rho", 0.0, ["rho", "> 0"]),
    ("damping", -1e-6, ["damping", ">= 0"]),
])
def test_bad_material(mesh, key, value, words):
    with pytest.raises(ValueError) as err:
        model(mesh, **{key: value})
    assert all(w in str(err.value) for w in words)


@pytest.mark.parametrize("params, words", [
    (dict(dt=0.0), ["dt", "> 0"]),
    (dict(dt=-1e-6), ["dt", "> 0"]),
    (dict(penalty=0.0), ["penalty", "> 0"]),
    (dict(mu=-0.1), ["mu", ">= 0"]),
    (dict(c_w=-1.0), ["c_w", ">= 0"]),
    (dict(rho_w=-1.0), ["rho_w", "> 0"]),   # Table 1's range (the registry's)
    (dict(g=-9.81), ["g", "> 0"]),
    (dict(y_w=np.inf), ["y_w", "finite"]),
    (dict(gravity="yes"), ["gravity", "True or False"]),
    (dict(energy_tolerance=0.0), ["energy_tolerance", "> 0"]),
    (dict(threads=-1), ["threads", ">= 0"]),
    (dict(stiffness=1.0), ["unknown parameter", "stiffness"]),
])
def test_bad_parameter(mesh, params, words):
    m = model(mesh)
    with pytest.raises(ValueError) as err:
        m.set(**params)
    assert all(w in str(err.value) for w in words)


def test_clockwise_and_degenerate_triangles(mesh):
    nodes, tri = mesh
    cw = tri.copy()
    cw[2] = cw[2, ::-1]
    with pytest.raises(ValueError, match="triangle 2 .*counter-clockwise"):
        engine.Model(nodes, cw, np.zeros(len(tri), int), MAT)
    flat = np.array([[0, 0], [1, 0], [2, 0], [0, 1]], float)
    with pytest.raises(ValueError, match="triangle 0 .*degenerate"):
        engine.Model(flat, [[0, 1, 2], [0, 1, 3]], [0, 0], MAT)


def test_node_ids_and_shapes(mesh):
    nodes, tri = mesh
    body = np.zeros(len(tri), int)
    bad = tri.copy()
    bad[0, 0] = len(nodes)
    with pytest.raises(ValueError, match=r"node ids must be in \[0, %d\]" % (len(nodes) - 1)):
        engine.Model(nodes, bad, body, MAT)
    with pytest.raises(ValueError, match="nodes must be an"):
        engine.Model(nodes[:, :1], tri, body, MAT)
    with pytest.raises(ValueError, match="one id per triangle"):
        engine.Model(nodes, tri, body[:-1], MAT)
    with pytest.raises(ValueError, match="not used by any triangle"):
        engine.Model(np.vstack((nodes, [[9.0, 9.0]])), tri, body, MAT)
    with pytest.raises(ValueError, match="finite"):
        engine.Model(np.where(nodes == 0.5, np.nan, nodes), tri, body, MAT)


def test_materials_and_node_sets(mesh):
    nodes, tri = mesh
    body = np.arange(len(tri)) % 2
    with pytest.raises(ValueError, match=r"no material for body id\(s\) \[1\]"):
        engine.Model(nodes, tri, body, {0: MAT})
    with pytest.raises(ValueError, match="body id must be in"):
        engine.Model(nodes, tri, body, {0: MAT, 5: MAT})
    with pytest.raises(ValueError, match="unknown key"):
        engine.Model(nodes, tri, body, dict(MAT, G=1.0))
    m = engine.Model(nodes, tri, body, MAT)
    with pytest.raises(ValueError, match=r"node set 'top'.*\[0, 11\]"):
        m.add_node_set("top", [0, 12])
    with pytest.raises(ValueError, match="no node set named"):
        m.fix("bottom")


def test_boundary_condition_errors(mesh):
    m = model(mesh)
    m.add_node_set("a", [0, 1])
    m.add_node_set("b", [1, 2])
    m.fix("a")
    with pytest.raises(ValueError, match="node 1 is already constrained by 'a'"):
        m.fix("b")
    with pytest.raises(ValueError, match="direction"):
        m.prescribe_velocity("b", direction=(0, 0), v_final=1.0, ramp_time=1.0)
    with pytest.raises(ValueError, match="ramp_time"):
        m.prescribe_velocity("b", direction=(0, 1), v_final=1.0, ramp_time=-1.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        m.prescribe_velocity("b", direction=(0, 1), table=([0.0, 0.0], [1.0, 2.0]), x=False)
    with pytest.raises(ValueError, match="dt is not set"):
        m.step(1)
    with pytest.raises(ValueError, match="n must be"):
        m.step(-1)
