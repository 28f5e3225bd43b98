"""Tests of abrakit.tensors: notation round trips, invariance of sigma:eps, stiffness, spectral split, Eq. (5.18)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from abrakit import tensors as T

finite = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)
matrices = arrays(np.float64, (3, 3), elements=finite)
batched = arrays(np.float64, st.tuples(st.integers(1, 4), st.just(3), st.just(3)), elements=finite)


def sym(A):
    return 0.5 * (A + np.swapaxes(A, -1, -2))


@given(batched)
def test_voigt_and_mandel_round_trips(A):
    S = sym(A)
    for kind in ("stress", "strain"):
        np.testing.assert_allclose(T.from_voigt(T.to_voigt(S, kind), kind), S, atol=1e-12)
    np.testing.assert_allclose(T.from_mandel(T.to_mandel(S)), S, atol=1e-12)


@given(matrices, matrices)
def test_double_contraction_is_the_same_in_every_notation(A, B):
    sig, eps = sym(A), sym(B)
    expected = np.sum(sig * eps)
    scale = 1.0 + abs(expected) + np.sum(np.abs(sig)) * np.sum(np.abs(eps))
    assert T.ddot(sig, eps) == pytest.approx(expected, abs=1e-12 * scale)
    assert T.to_voigt(sig, "stress") @ T.to_voigt(eps, "strain") == pytest.approx(expected, abs=1e-12 * scale)
    assert T.to_mandel(sig) @ T.to_mandel(eps) == pytest.approx(expected, abs=1e-12 * scale)


def test_voigt_order_and_engineering_shears_eq_2_17():
    eps = np.array([[1.0, 6.0, 5.0], [6.0, 2.0, 4.0], [5.0, 4.0, 3.0]])
    np.testing.assert_array_equal(T.to_voigt(eps, "strain"), [1, 2, 3, 8, 10, 12])
    np.testing.assert_array_equal(T.to_voigt(eps, "stress"), [1, 2, 3, 4, 5, 6])
    assert T.norm(eps) == pytest.approx(np.linalg.norm(T.to_mandel(eps)))


@given(matrices)
def test_dev_is_traceless_and_projector_agrees(A):
    S = sym(A)
    assert T.trace(T.dev(S)) == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(T.ddot42(T.identity4_dev(), S), T.dev(S), atol=1e-9)
    np.testing.assert_allclose(T.ddot42(T.identity4_sym(), S), S, atol=1e-9)
    np.testing.assert_allclose(T.ddot42(T.identity4_vol(), S), T.trace(S) / 3 * np.eye(3), atol=1e-9)


@given(
    st.floats(1.0, 1e6),
    st.floats(-0.99, 0.49),
    matrices,
)
@settings(max_examples=50)
def test_isotropic_stiffness_in_all_notations(E, nu, A):
    eps = sym(A) * 1e-3
    C = T.isotropic_stiffness(E, nu)
    sig = T.ddot42(C, eps)
    lam, mu = T.lame(E, nu)
    np.testing.assert_allclose(sig, lam * np.trace(eps) * np.eye(3) + 2 * mu * eps, rtol=1e-10, atol=1e-12 * E)
    Cv = T.isotropic_stiffness(E, nu, "voigt")
    np.testing.assert_allclose(Cv @ T.to_voigt(eps, "strain"), T.to_voigt(sig), rtol=1e-10, atol=1e-12 * E)
    Cm = T.isotropic_stiffness(E, nu, "mandel")
    np.testing.assert_allclose(Cm @ T.to_mandel(eps), T.to_mandel(sig), rtol=1e-10, atol=1e-12 * E)
    # major and minor symmetries, positive definiteness (eigenvalues 3K and 2 mu)
    np.testing.assert_allclose(C, np.transpose(C, (2, 3, 0, 1)))
    np.testing.assert_allclose(C, np.transpose(C, (1, 0, 2, 3)))
    np.testing.assert_allclose(C, np.transpose(C, (0, 1, 3, 2)))
    eig = np.linalg.eigvalsh(Cm)
    assert eig.min() > 0
    np.testing.assert_allclose(sorted(eig), sorted([3 * lam + 2 * mu] + [2 * mu] * 5), rtol=1e-10)


def test_compliance_matrix_inverts_stiffness_in_voigt():
    E, nu = 200e3, 0.3
    C = T.isotropic_stiffness(E, nu)
    S = T.from_mandel4(np.linalg.inv(T.to_mandel4(C)))
    Sv = T.to_voigt4(S, "compliance")
    np.testing.assert_allclose(Sv @ T.isotropic_stiffness(E, nu, "voigt"), np.eye(6), atol=1e-12)
    assert Sv[0, 0] == pytest.approx(1 / E)
    assert Sv[0, 1] == pytest.approx(-nu / E)
    assert Sv[5, 5] == pytest.approx(2 * (1 + nu) / E)
    np.testing.assert_allclose(T.from_voigt4(Sv, "compliance"), S, atol=1e-18)


@given(arrays(np.float64, (6, 6), elements=finite))
def test_fourth_order_round_trip(M):
    Msym = 0.5 * (M + M.T)
    for kind in ("stiffness", "compliance", "mandel"):
        np.testing.assert_allclose(T.to_voigt4(T.from_voigt4(Msym, kind), kind), Msym, atol=1e-9)


@given(batched)
def test_positive_plus_negative_part_is_the_tensor_eq_6_57(A):
    S = sym(A)
    pos, neg = T.positive_part(S), T.negative_part(S)
    np.testing.assert_allclose(pos + neg, S, atol=1e-9 * (1 + np.abs(S).max()))
    assert np.all(np.linalg.eigvalsh(pos) >= -1e-9 * (1 + np.abs(S).max()))
    assert np.all(np.linalg.eigvalsh(neg) <= 1e-9 * (1 + np.abs(S).max()))
    # the two parts are orthogonal: eps+ : eps- = 0
    np.testing.assert_allclose(T.ddot(pos, neg), 0.0, atol=1e-6 * (1 + np.abs(S).max() ** 2))


def test_positive_part_of_uniaxial_and_repeated_eigenvalues():
    np.testing.assert_array_equal(T.positive_part(np.diag([1.0, -2.0, 0.0])), np.diag([1.0, 0.0, 0.0]))
    np.testing.assert_allclose(T.positive_part(np.eye(3)), np.eye(3))
    np.testing.assert_allclose(T.positive_part(-np.eye(3)), 0 * np.eye(3))
    with pytest.raises(ValueError, match="eps"):
        T.positive_part(np.full((3, 3), np.nan))


@pytest.mark.parametrize("degree", [2, 4, 6, 8, 12])
def test_sphere_quadrature_is_exact_for_monomials(degree):
    n, w = T.sphere_quadrature(degree)
    assert w.sum() == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0)
    from math import gamma

    def exact(a, b, c):  # average of x^a y^b z^c over the unit sphere
        if a % 2 or b % 2 or c % 2:
            return 0.0
        beta = lambda *p: np.prod([gamma((q + 1) / 2) for q in p]) / gamma(sum((q + 1) / 2 for q in p))
        return beta(a, b, c) / (4 * np.pi) * 2

    for a in range(degree + 1):
        for b in range(degree + 1 - a):
            for c in range(degree + 1 - a - b):
                got = np.sum(w * n[:, 0] ** a * n[:, 1] ** b * n[:, 2] ** c)
                assert got == pytest.approx(exact(a, b, c), abs=1e-14), (a, b, c)


@given(matrices)
def test_direction_averages_reproduce_eq_5_18(A):
    sigma = sym(A)
    nn = T.sphere_average(lambda n: np.einsum("mi,mj->mij", n, n), degree=2)
    np.testing.assert_allclose(nn, np.eye(3) / 3, atol=1e-15)
    nnnn_sigma = T.sphere_average(lambda n: np.einsum("mi,mj,mk,ml,kl->mij", n, n, n, n, sigma), degree=4)
    expected = T.fourth_moment_contraction(sigma)
    np.testing.assert_allclose(nnnn_sigma, expected, atol=1e-13 * (1 + np.abs(sigma).max()))


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="nu"):
        T.isotropic_stiffness(1.0, 0.5)
    with pytest.raises(ValueError, match="E"):
        T.isotropic_stiffness(-1.0, 0.3)
    with pytest.raises(ValueError, match="kind"):
        T.to_voigt(np.eye(3), "engineering")
    with pytest.raises(ValueError, match=r"A must have shape"):
        T.to_voigt(np.eye(2))
    with pytest.raises(ValueError, match="notation"):
        T.isotropic_stiffness(1.0, 0.3, "kelvin")
    with pytest.raises(ValueError, match="degree"):
        T.sphere_quadrature(-1)
    with pytest.raises(ValueError, match="one value per direction"):
        T.sphere_average(lambda n: np.ones(3))
