"""tensormass.kernels() and tensormass.kernel(): the registry from Python.

Checked against finite differences, an independent NumPy StVK, per-element
calls, and every error path."""
import numpy as np
import pytest

import tensormass as tm

MATERIAL = dict(young=2.0e6, poisson=0.3)
REFERENCE_NODES = {
    "tet4": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
    "tri3": [[0, 0], [1, 0], [0, 1]],
    "hex8": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
}


def batch(element, count=4, strain=0.05, seed=1):
    """`count` distorted copies of the element and small displacements: (n, nodes, dim) each."""
    random = np.random.default_rng(seed)
    nodes = np.array(REFERENCE_NODES[element], float)
    rest = nodes[None] * 0.02 + 0.002 * random.standard_normal((count, *nodes.shape))
    u = strain * 0.02 * random.standard_normal(rest.shape)
    return rest, u


def test_kernels_lists_the_registry():
    kernels = tm.kernels()
    laws = {k["law"] for k in kernels}
    elements = {k["element"] for k in kernels}
    triples = {(k["law"], k["element"], k["split"]) for k in kernels}
    assert len(triples) == len(kernels)
    assert all((law, element, "whole") in triples for law in laws for element in elements)
    stvk = next(k for k in kernels if (k["law"], k["element"], k["split"]) == ("stvk", "tet4", "whole"))
    assert stvk["nodes"] == 4 and stvk["dim"] == 3 and stvk["dofs"] == 12
    assert stvk["parameters"] == ["young", "poisson"]
    assert stvk["limits"] == ["> 0", "> -1 and < 0.5"]
    assert stvk["flops_hessian"] > stvk["flops_gradient"] > 0
    assert "stable_neohookean" in {k["law"] for k in kernels if k["invertible"]}


@pytest.mark.parametrize("law,element", [("stvk", "tet4"), ("neohookean", "hex8"), ("corotational", "tri3"),
                                         ("stable_neohookean", "tet4"), ("hooke", "hex8")])
def test_gradient_and_hessian_are_the_derivatives(law, element):
    k = tm.kernel(law, element, "whole")
    rest, u = batch(element)
    g = k.gradient(rest, u, **MATERIAL)
    H = k.hessian(rest, u, **MATERIAL)
    assert g.shape == (len(rest), k.dofs) and H.shape == (len(rest), k.dofs, k.dofs)
    h = 1e-7 * 0.02
    for dof in range(k.dofs):
        step = np.zeros_like(u)
        step.reshape(len(u), -1)[:, dof] = h
        energy_slope = (k.energy(rest, u + step, **MATERIAL) - k.energy(rest, u - step, **MATERIAL)) / (2 * h)
        np.testing.assert_allclose(energy_slope, g[:, dof], rtol=1e-5, atol=1e-6 * np.abs(g).max())
        force_slope = (k.gradient(rest, u + step, **MATERIAL) - k.gradient(rest, u - step, **MATERIAL)) / (2 * h)
        np.testing.assert_allclose(force_slope, H[:, :, dof], rtol=1e-5, atol=1e-6 * np.abs(H).max())


def stvk_tet4_energy(rest, u, young, poisson):
    """St Venant-Kirchhoff on a linear tetrahedron, written out in NumPy."""
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    energies = []
    for X, U in zip(rest, u):
        dX = (X[1:] - X[0]).T  # columns: edges at rest
        dx = (X[1:] + U[1:] - X[0] - U[0]).T
        F = dx @ np.linalg.inv(dX)
        E = 0.5 * (F.T @ F - np.eye(3))
        volume = abs(np.linalg.det(dX)) / 6
        energies.append(volume * (lam / 2 * np.trace(E) ** 2 + mu * np.trace(E @ E)))
    return np.array(energies)


def test_stvk_energy_matches_an_independent_formula():
    rest, u = batch("tet4", count=6, strain=0.3)
    k = tm.kernel("stvk", "tet4")
    np.testing.assert_allclose(k.energy(rest, u, **MATERIAL), stvk_tet4_energy(rest, u, **MATERIAL), rtol=1e-12)


def tet4_deformation_gradients(rest, u):
    """F of each linear tetrahedron, and its rest volume."""
    for X, U in zip(rest, u):
        dX = (X[1:] - X[0]).T
        dx = (X[1:] + U[1:] - X[0] - U[0]).T
        yield dx @ np.linalg.inv(dX), abs(np.linalg.det(dX)) / 6


def test_a_law_takes_its_own_constants():
    """Mooney-Rivlin (c10, c01, kappa) against its energy written out in NumPy."""
    rest, u = batch("tet4", count=6, strain=0.3)
    constants = dict(c10=3.0e5, c01=8.0e4, kappa=2.0e7)
    expected = []
    for F, volume in tet4_deformation_gradients(rest, u):
        C = F.T @ F
        J = np.linalg.det(F)
        I1, I2 = np.trace(C), (np.trace(C) ** 2 - np.trace(C @ C)) / 2
        density = (constants["c10"] * (J ** (-2 / 3) * I1 - 3) + constants["c01"] * (J ** (-4 / 3) * I2 - 3)
                   + constants["kappa"] / 2 * (J - 1) ** 2)
        expected.append(volume * density)
    k = tm.kernel("mooney_rivlin", "tet4")
    np.testing.assert_allclose(k.energy(rest, u, **constants), expected, rtol=1e-11)
    with pytest.raises(ValueError, match="missing parameter 'c10'"):
        k.energy(rest, u, **MATERIAL)
    with pytest.raises(ValueError, match="kappa must be > 0 for law mooney_rivlin"):
        k.energy(rest, u, **dict(constants, kappa=-1.0))


def test_a_batch_equals_its_elements_one_by_one():
    rest, u = batch("hex8", count=5)
    k = tm.kernel("neohookean", "hex8")
    together = k.hessian(rest, u, **MATERIAL)
    for e in range(len(rest)):
        alone = k.hessian(rest[e:e + 1], u[e:e + 1], **MATERIAL)
        np.testing.assert_array_equal(alone[0], together[e])


def test_integer_and_non_contiguous_arrays_are_converted():
    rest, u = batch("tet4", count=3)
    k = tm.kernel("stvk", "tet4")
    expected = k.energy(rest, u, **MATERIAL)
    np.testing.assert_array_equal(k.energy(np.asfortranarray(rest), np.asfortranarray(u), **MATERIAL), expected)
    ones = np.ones((1, 4, 3), dtype=np.int64)
    assert k.energy(ones * 0 + np.array(REFERENCE_NODES["tet4"]), 0 * ones, **MATERIAL)[0] == 0.0


def test_errors_are_value_errors_naming_the_problem():
    k = tm.kernel("stvk", "tet4")
    rest, u = batch("tet4", count=2)
    with pytest.raises(ValueError, match=r"rest must have shape \(n, 4, 3\) for tet4"):
        k.energy(rest[:, :3], u, **MATERIAL)
    with pytest.raises(ValueError, match="rest and u hold 2 and 1 elements"):
        k.energy(rest, u[:1], **MATERIAL)
    with pytest.raises(ValueError, match="missing parameter 'poisson'"):
        k.energy(rest, u, young=1e6)
    with pytest.raises(ValueError, match="unknown parameter 'density' for law stvk"):
        k.energy(rest, u, density=1000, **MATERIAL)
    with pytest.raises(ValueError, match="poisson must be > -1 and < 0.5 for law stvk, got 0.5"):
        k.energy(rest, u, young=1e6, poisson=0.5)
    flipped = rest.copy()
    flipped[1, [1, 2]] = flipped[1, [2, 1]]
    with pytest.raises(ValueError, match="element 1: non-positive rest Jacobian"):
        k.energy(flipped, u, **MATERIAL)
    with pytest.raises(ValueError, match=r"no kernel stvk/tet5/whole \(see tensormass.kernels\(\)\)"):
        tm.kernel("stvk", "tet5")
    assert issubclass(tm.NumericalError, RuntimeError)
