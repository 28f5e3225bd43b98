"""Traction–opening softening laws whose area is a fracture toughness (seed 001, "Damage Evolution").

A softening law gives the traction a crack plane still carries after it has opened by ``delta`` (mm):

    S(delta) = sigma_c F(delta),      F(0) = 1,      integral_0^inf S(delta) d delta = G_c,

with the strength ``sigma_c`` (MPa) and the toughness ``G_c`` (N/mm = MPa mm). Two laws are offered:

- ``linear``:      F = 1 - delta/delta_c,  delta_c = 2 G_c / sigma_c  (zero beyond delta_c);
- ``exponential``: F = exp(-sigma_c delta / G_c)  (never exactly zero; 99 % of G_c is spent at 4.6 G_c/sigma_c).

In a crack band of width ``h`` the opening is smeared into the cracking strain ``delta / h``. A point of modulus
``M`` on its softening branch satisfies ``M (e - delta/h) = S(delta)``, which has one solution for every strain
``e`` only while ``M/h > max |S'|``: the band must be narrower than

    h_max = M / max |S'| = M G_c / sigma_c^2 × (2 for linear, 1 for exponential),

otherwise the point snaps back (Bažant & Oh 1983; Nairn, Hammerquist & Aimene 2017). Strength and toughness may be
arrays (one value per point, e.g. from :mod:`abrakit.materials.strength_statistics`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..validation import check_option, check_positive


@dataclass(frozen=True)
class LinearSoftening:
    """``S = sigma_c (1 - delta/delta_c)``, ``delta_c = 2 G_c/sigma_c``: the softening law of seed 001's example."""

    name: str = "linear"
    #: ``h_max = factor * M G_c / sigma_c**2`` (``max|S'| = sigma_c / delta_c``).
    band_factor: float = 2.0

    @staticmethod
    def failure_opening(strength, toughness):
        """``delta_c = 2 G_c / sigma_c`` (mm), the opening at which the traction vanishes."""
        return 2.0 * np.asarray(toughness, dtype=float) / np.asarray(strength, dtype=float)

    def traction(self, delta, strength, toughness):
        """``S(delta)`` (MPa)."""
        return np.asarray(strength) * np.clip(1.0 - delta / self.failure_opening(strength, toughness), 0.0, None)

    def opening(self, traction, strength, toughness):
        """The opening at which the law carries ``traction`` (0 < traction <= strength), the inverse of S."""
        return self.failure_opening(strength, toughness) * (1.0 - np.asarray(traction) / np.asarray(strength))

    def energy(self, delta, strength, toughness):
        """``integral_0^delta S`` (N/mm): the toughness spent on the way to ``delta``."""
        delta_c = self.failure_opening(strength, toughness)
        x = np.clip(delta / delta_c, 0.0, 1.0)
        return np.asarray(toughness) * x * (2.0 - x)


@dataclass(frozen=True)
class ExponentialSoftening:
    """``S = sigma_c exp(-sigma_c delta / G_c)``: steepest at the start, the whole tail carries toughness."""

    name: str = "exponential"
    band_factor: float = 1.0

    @staticmethod
    def failure_opening(strength, toughness):
        """``inf``: the traction never vanishes (the damage reaches ``d_max`` instead)."""
        return np.full(np.broadcast_shapes(np.shape(strength), np.shape(toughness)), np.inf)

    def traction(self, delta, strength, toughness):
        strength = np.asarray(strength)
        return strength * np.exp(-strength * delta / np.asarray(toughness))

    def opening(self, traction, strength, toughness):
        strength = np.asarray(strength)
        return -np.asarray(toughness) / strength * np.log(np.asarray(traction) / strength)

    def energy(self, delta, strength, toughness):
        strength, toughness = np.asarray(strength), np.asarray(toughness)
        return toughness * -np.expm1(-strength * delta / toughness)


SOFTENING_LAWS = {"linear": LinearSoftening(), "exponential": ExponentialSoftening()}


def softening_law(name: str):
    """The softening law called ``name`` (``"linear"`` or ``"exponential"``)."""
    return SOFTENING_LAWS[check_option("softening law", name, SOFTENING_LAWS)]


def max_band_width(law, modulus, strength, toughness):
    """``h_max = factor M G_c / sigma_c^2`` (mm): the widest crack band without a local snap-back."""
    modulus, strength = check_positive("modulus", modulus), check_positive("strength", strength)
    toughness = check_positive("toughness", toughness)
    return law.band_factor * np.asarray(modulus) * np.asarray(toughness) / np.asarray(strength) ** 2
