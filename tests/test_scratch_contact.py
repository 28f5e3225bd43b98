"""Tests of abrakit.scratch.contact: penalty contact with Coulomb friction, Eq. (8.1)-(8.4), and its tangent."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from abrakit.scratch import ConicalIndenter, SphericalIndenter, contact_response, initial_state
from abrakit.scratch.contact import OPEN, SLIP, STICK, penalty_from_stiffness

R = 0.05
C_N = 2.1e8            # E/h for steel and h = 1 um, N/mm^3
MU = 0.1


def respond(indenter, x, x_old, tip, tip_old, state, geometric=True, **kw):
    """The law as the solver calls it: kinematics from the indenter at the current point positions x."""
    sg = indenter.gap(x, tip)
    increment = (x - x_old) - (tip - tip_old)
    kw = {"c_N": C_N, "mu": MU} | kw
    return contact_response(sg.gap, sg.normal, increment, state,
                            normal_gradient=sg.normal_gradient if geometric else None, **kw)


def scene(seed, n=40, indenter=None):
    """Points scattered just inside/outside the apex region of a tip that moved along +z, with a random old
    elastic slip in the old tangent plane."""
    rng = np.random.default_rng(seed)
    indenter = indenter or SphericalIndenter(R)
    tip_old = np.array([0.0, -0.002, 0.0])
    tip = tip_old + [0.0, 0.0, 2e-6]
    # a sphere-tipped cone of half-angle 60 deg leaves its cap at rho = R/2: reach onto the flank too
    rho = rng.uniform(0.0, 0.012 if isinstance(indenter, SphericalIndenter) else 0.04, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    surf = tip + np.stack([rho * np.cos(phi), indenter.height(rho), rho * np.sin(phi)], axis=1)
    normal = indenter.gap(surf, tip).normal
    x = surf + rng.uniform(-2e-5, 5e-6, n)[:, None] * normal
    # increments and old elastic slips over many decades, so every penalty c_T sees stick and slip
    x_old = x - (tip - tip_old) - rng.normal(0.0, 1.0, (n, 3)) * 10 ** rng.uniform(-10, -4.5, (n, 1))
    state = initial_state(n)
    t_plane = rng.normal(0.0, 1.0, (n, 3)) * 10 ** rng.uniform(-10, -5, (n, 1))
    state["elastic_slip"] = t_plane - np.sum(t_plane * normal, axis=1)[:, None] * normal
    return indenter, x, x_old, tip, tip_old, state


def fd_tangent(indenter, x, x_old, tip, tip_old, state, h=1e-11, **kw):
    J = np.zeros((x.shape[0], 3, 3))
    for j in range(3):
        dx = np.zeros(3)
        dx[j] = h
        up = respond(indenter, x + dx, x_old, tip, tip_old, state, **kw).traction
        down = respond(indenter, x - dx, x_old, tip, tip_old, state, **kw).traction
        J[:, :, j] = (up - down) / (2 * h)
    return J


@pytest.mark.parametrize("indenter", [SphericalIndenter(R), ConicalIndenter(R, 60.0)], ids=["sphere", "cone60"])
@pytest.mark.parametrize("c_T", [C_N, 1e7, 1e10])
def test_tangent_matches_finite_differences_in_stick_slip_and_open(indenter, c_T):
    indenter, x, x_old, tip, tip_old, state = scene(0, n=120, indenter=indenter)
    if isinstance(indenter, ConicalIndenter):
        rel = x - tip
        assert np.sum(np.hypot(rel[:, 0], rel[:, 2]) > 0.03) > 20           # points on the flank
    out = respond(indenter, x, x_old, tip, tip_old, state, c_T=c_T)
    J_fd = fd_tangent(indenter, x, x_old, tip, tip_old, state, c_T=c_T)
    status = out.state["status"]
    # a few points may sit within the stencil of a stick/slip kink: require 95 %, and the median, to match
    scale = np.abs(out.tangent).max(axis=(1, 2)) + 1.0
    for code in (OPEN, STICK, SLIP):
        sel = status == code
        assert sel.sum() >= 3, f"scene lacks status {code}"
        err = np.abs(out.tangent[sel] - J_fd[sel]).max(axis=(1, 2)) / scale[sel]
        assert np.median(err) < 1e-6 and np.mean(err < 5e-6) > 0.95
    np.testing.assert_array_equal(out.tangent[status == OPEN], 0.0)


def test_geometric_terms_matter_for_the_curved_tip_and_are_exact():
    """Dropping dn/dx leaves the traction unchanged but the tangent misses p G: the full one matches FD."""
    indenter, x, x_old, tip, tip_old, state = scene(1, n=60)
    full = respond(indenter, x, x_old, tip, tip_old, state)
    flat = respond(indenter, x, x_old, tip, tip_old, state, geometric=False)
    np.testing.assert_array_equal(full.traction, flat.traction)
    J_fd = fd_tangent(indenter, x, x_old, tip, tip_old, state)
    closed = full.state["status"] != OPEN
    err_full = np.abs(full.tangent - J_fd)[closed].max()
    err_flat = np.abs(flat.tangent - J_fd)[closed].max()
    assert err_flat > 100 * err_full


def test_open_points_carry_nothing_and_reset_the_elastic_slip():
    state = initial_state(2)
    state["elastic_slip"] = np.array([[1e-6, 0, 0], [0, 0, 2e-6]])
    state["slip_path"] = np.array([0.3, 0.4])
    out = contact_response([1e-4, 0.0], [[0, -1, 0], [0, -1, 0]], np.ones((2, 3)) * 1e-6, state, c_N=C_N)
    np.testing.assert_array_equal(out.traction, 0.0)
    np.testing.assert_array_equal(out.tangent, 0.0)
    np.testing.assert_array_equal(out.pressure, 0.0)
    np.testing.assert_array_equal(out.state["elastic_slip"], 0.0)
    np.testing.assert_array_equal(out.state["slip_path"], [0.3, 0.4])
    np.testing.assert_array_equal(out.state["status"], [OPEN, OPEN])


def test_normal_penalty_eq_8_3_and_penetration_bound():
    g = np.array([-1e-6, -3e-6])
    out = contact_response(g, [[0, -1, 0]] * 2, np.zeros((2, 3)), initial_state(2), c_N=C_N)
    np.testing.assert_allclose(out.pressure, -C_N * g)                  # p = -t_N = -c_N g_N
    np.testing.assert_allclose(out.traction, np.outer(-C_N * g, [0, -1, 0]))
    np.testing.assert_array_equal(out.state["status"], [STICK, STICK])
    # the penetration a pressure p needs is p / c_N = (p / E) h: at the hardness of steel, 2 GPa, about 1 % of h
    assert 2000.0 / penalty_from_stiffness(210000.0, 0.001) == pytest.approx(2000.0 / 210000.0 * 0.001)


def test_stick_then_slip_when_dragged_and_friction_opposes_the_relative_motion():
    """A point under a tip sliding along +z: the friction drags it along +z; |t_T| = mu p once it slips."""
    n_steps, dz = 8, 3e-7
    tip = np.array([0.0, -0.002, 0.0])
    x = tip + [0.0, 1e-5, 0.0]
    indenter, state, ratios, status = SphericalIndenter(R), initial_state(1), [], []
    for _ in range(n_steps):
        new_tip = tip + [0.0, 0.0, dz]
        out = respond(indenter, x[None], x[None], new_tip, tip, state)
        n = indenter.gap(x[None], new_tip).normal[0]
        t_T = out.traction[0] - (out.traction[0] @ n) * n
        ratios.append(np.linalg.norm(t_T) / out.pressure[0])
        status.append(out.state["status"][0])
        assert t_T[2] > 0 and abs(t_T[0]) < 1e-12 * np.linalg.norm(t_T)
        state, tip = out.state, new_tip
    assert status[:3] == [STICK] * 3 and status[-1] == SLIP
    np.testing.assert_allclose(ratios[:3], np.arange(1, 4) * C_N * dz / (C_N * 1e-5), rtol=1e-3)
    np.testing.assert_allclose(ratios[4:], MU, rtol=1e-12)
    # the slip path is the tip travel minus the elastic slip mu p / c_T kept at the end (up to the slight
    # rotation of the normal under the moving sphere, dz n_steps / R = 5e-5)
    p = C_N * 1e-5
    assert state["slip_path"][0] == pytest.approx(n_steps * dz - MU * p / C_N, rel=1e-4)


# mu: frictionless or physical (>= 1e-6); below that the limit mu p itself becomes subnormal
@given(st.floats(1e-9, 1e-5), st.floats(1e-10, 1e-4), st.one_of(st.just(0.0), st.floats(1e-6, 1.0)),
       st.floats(1e6, 1e11))
@settings(max_examples=200, deadline=None)
def test_coulomb_limit_always_holds(penetration, slip, mu, c_T):
    n = np.array([[0.0, -1.0, 0.0]])
    out = contact_response([-penetration], n, [[slip, 0.3 * slip, -slip]], initial_state(1), c_N=C_N, c_T=c_T,
                           mu=mu)
    t = out.traction[0]
    t_T = t - (t @ n[0]) * n[0]
    assert t @ n[0] == pytest.approx(out.pressure[0]) and out.pressure[0] >= 0
    limit = mu * out.pressure[0]
    if limit > 0.0:
        # measured relative to the limit: the squares of components near 1e-156 would underflow in norm()
        assert np.linalg.norm(t_T / limit) <= 1 + 1e-12
    else:
        assert np.all(t_T == 0.0)
    # the stored elastic slip reproduces the tangential traction: t_T = -c_T e
    np.testing.assert_allclose(t_T, -c_T * out.state["elastic_slip"][0], rtol=1e-10, atol=1e-300)


def test_traction_is_continuous_across_the_stick_slip_limit():
    n = np.array([[0.0, -1.0, 0.0]])
    p = C_N * 1e-6
    limit = MU * p / C_N                          # elastic slip at which stick turns into slip
    slips = limit * np.array([1 - 1e-9, 1.0, 1 + 1e-9])
    out = contact_response(np.full(3, -1e-6), np.repeat(n, 3, axis=0), np.outer(slips, [1.0, 0, 0]),
                           initial_state(3), c_N=C_N, mu=MU)
    np.testing.assert_array_equal(out.state["status"], [STICK, STICK, SLIP])
    np.testing.assert_allclose(out.traction[:, 0], -MU * p, rtol=2e-9)
    np.testing.assert_allclose(out.traction[0], out.traction[2], rtol=2e-9)


def test_frame_invariance():
    indenter, x, x_old, tip, tip_old, state = scene(4, n=50)
    sg = indenter.gap(x, tip)
    inc = (x - x_old) - (tip - tip_old)
    Q = Rotation.from_euler("xyz", [0.3, -1.1, 2.0]).as_matrix()
    out = contact_response(sg.gap, sg.normal, inc, state, c_N=C_N, mu=MU, normal_gradient=sg.normal_gradient)
    rotated = dict(state, elastic_slip=state["elastic_slip"] @ Q.T)
    rot = contact_response(sg.gap, sg.normal @ Q.T, inc @ Q.T, rotated, c_N=C_N, mu=MU,
                           normal_gradient=Q @ sg.normal_gradient @ Q.T)
    np.testing.assert_allclose(rot.traction, out.traction @ Q.T, atol=1e-9 * np.abs(out.traction).max())
    np.testing.assert_allclose(rot.tangent, Q @ out.tangent @ Q.T, atol=1e-9 * np.abs(out.tangent).max())
    np.testing.assert_allclose(rot.state["elastic_slip"], out.state["elastic_slip"] @ Q.T, atol=1e-18)
    np.testing.assert_array_equal(rot.state["status"], out.state["status"])


def test_old_state_is_never_mutated():
    indenter, x, x_old, tip, tip_old, state = scene(5, n=30)
    for value in state.values():
        value.flags.writeable = False
    before = {k: v.copy() for k, v in state.items()}
    out = respond(indenter, x, x_old, tip, tip_old, state)
    for k in before:
        np.testing.assert_array_equal(state[k], before[k])
        assert out.state[k] is not state[k]


def test_normal_tangent_is_symmetric_and_frictionless_slip_carries_no_shear():
    indenter, x, x_old, tip, tip_old, state = scene(6, n=40)
    out = respond(indenter, x, x_old, tip, tip_old, state, mu=0.0)
    closed = out.state["status"] != OPEN
    assert np.all(out.state["status"][closed] == SLIP) or np.all(np.linalg.norm(state["elastic_slip"], axis=1) == 0)
    sg = indenter.gap(x, tip)
    np.testing.assert_allclose(out.traction, out.pressure[:, None] * sg.normal, rtol=1e-12, atol=0)
    np.testing.assert_allclose(out.tangent, np.swapaxes(out.tangent, 1, 2), atol=1e-6 * np.abs(out.tangent).max())


def test_penalty_from_stiffness_and_bad_input():
    assert penalty_from_stiffness(210000.0, 0.001) == pytest.approx(2.1e8)
    assert penalty_from_stiffness(210000.0, 0.002, factor=10.0) == pytest.approx(1.05e9)
    np.testing.assert_allclose(penalty_from_stiffness(210000.0, np.array([0.001, 0.004])), [2.1e8, 5.25e7])
    with pytest.raises(ValueError, match="h"):
        penalty_from_stiffness(210000.0, 0.0)
    n = [[0.0, -1.0, 0.0]]
    with pytest.raises(ValueError, match="unit"):
        contact_response([-1e-6], [[0.0, -2.0, 0.0]], [[0, 0, 0]], initial_state(1), c_N=C_N)
    with pytest.raises(ValueError, match="mu"):
        contact_response([-1e-6], n, [[0, 0, 0]], initial_state(1), c_N=C_N, mu=-0.1)
    with pytest.raises(ValueError, match="c_N"):
        contact_response([-1e-6], n, [[0, 0, 0]], initial_state(1), c_N=0.0)
    with pytest.raises(ValueError, match="state"):
        contact_response([-1e-6], n, [[0, 0, 0]], {}, c_N=C_N)
    with pytest.raises(ValueError, match="increment"):
        contact_response([-1e-6, -1e-6], n * 2, [[0, 0, 0]], initial_state(2), c_N=C_N)
    with pytest.raises(ValueError, match="gap"):
        contact_response([np.nan], n, [[0, 0, 0]], initial_state(1), c_N=C_N)
