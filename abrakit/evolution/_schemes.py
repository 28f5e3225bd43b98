"""Time discretisations of the 1D evolution laws (Eq. 2.110 ff.): which time levels of ε and λ the driving force
p(ε, λ) takes, and the time stepping that :class:`abrakit.evolution.Damage1D` and
:class:`abrakit.evolution.Plasticity1D` share, with the checks of a model and of its initial state that the
drivers share."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from abrakit.validation import broadcast_shapes, check_finite, check_instance, check_option, check_positive

if TYPE_CHECKING:
    from abrakit.evolution import Dissipation

#: Time discretisations listed after Eq. (2.110): (time level of the strain, time level of λ) in p(ε, λ).
SCHEMES = {
    "explicit": ("m", "m"),  # p(ε^m, λ^m): forward Euler
    "implicit": ("m+1", "m+1"),  # p(ε^{m+1}, λ^{m+1}): backward Euler
    "split": ("m+1", "m"),  # p(ε^{m+1}, λ^m): operator split used by the seed's FEM, Eqs. (4.47), (4.53)
    "split_reverse": ("m", "m+1"),  # p(ε^m, λ^{m+1}): the other operator split
}


class _Model1D:
    """Shared time stepping: the scheme picks the strain level and the λ level of the driving force."""

    def update(self, state_m, eps_m, eps_new, dt, dissipation: Dissipation, scheme: str = "implicit", **kw):
        """New state after one step, for a scheme of :data:`SCHEMES` or ``"variational"`` (numerical).

        Rate-dependent: the λ level m gives a forward step λ^m + Δt λ̇(ε*, λ^m) (Eqs. 2.112, 4.53), the level
        m+1 a backward step solved in closed form. Rate-independent: Δρ follows from the consistency condition
        Φ(ε*, λ^{m+1}) = 0 (Eqs. 2.109, 2.110, 4.49) whatever the λ level; only the strain level ε* matters.
        """
        dt = check_positive("dt", dt)
        if scheme == "variational":
            return self.variational_step(eps_new, state_m, dt, dissipation, **kw)
        strain_level, lambda_level = SCHEMES[check_option("scheme", scheme, (*SCHEMES, "variational"))]
        eps_star = eps_new if strain_level == "m+1" else eps_m
        if dissipation.is_rate_independent or lambda_level == "m+1":
            return self.backward_step(eps_star, state_m, dt, dissipation)
        return self.forward_step(eps_star, state_m, dt, dissipation)

    def forward_step(self, eps, state_m, dt, dissipation: Dissipation):
        """λ^{m+1} = λ^m + Δt λ̇(ε, λ^m): Eq. (2.112) (corrected switch) with p at (ε, λ^m), Eq. (4.53)."""
        rates = self.state_rate(eps, state_m, dissipation)
        return type(state_m)._make(np.asarray(x, float) + dt * r for x, r in zip(state_m, rates, strict=True))

    def consistency_parameter(self, eps, state_m, state):
        """Δρ = |Δλ| / |p(ε, λ^{m+1})| [1/MPa], Eq. (2.105) in increments: λ^{m+1} - λ^m = Δρ p (Eq. 2.109)."""
        step = np.abs(np.asarray(state[0], float) - np.asarray(state_m[0], float))
        p = np.abs(self.driving_force(eps, state))
        return np.divide(step, p, out=np.zeros(np.broadcast(step, p).shape), where=step > 0)


def _check_model(model):
    """``model`` if it is one of the 1D models (:class:`Damage1D`, :class:`Plasticity1D`), else ``TypeError``."""
    if not isinstance(model, _Model1D):
        raise TypeError(f"model must be a Damage1D or Plasticity1D, got {model!r}")
    return model


def _check_state0(model, state0, shape=()):
    """``state0`` if it is ``None`` or a finite state of ``model`` whose fields broadcast to ``shape``."""
    if state0 is None:
        return None
    kind = type(model.initial_state())
    check_instance("state0", state0, kind)
    for name, value in zip(state0._fields, state0, strict=True):
        check_finite(f"state0.{name}", value)
        if broadcast_shapes(**{f"state0.{name}": value, "points": np.broadcast_to(0.0, shape)}) != tuple(shape):
            raise ValueError(f"state0.{name} must broadcast to the points' shape {tuple(shape)}, "
                             f"got {np.shape(value)}")
    return kind(*state0)                               # the state's own checks: d >= 0, alpha >= 0
