"""What the toolkit reproduces from the seed and how far it is off: claims, verdicts and the table they make.

A :class:`Claim` is one figure or table of the seed: the seed's value, ours, the deviation and a verdict
(``reproduced``: within 1 % or the printed digits; ``close``: within 5–15 %; ``differs``; ``not computed``).
:func:`recomputed` gives the claims the package computes itself in seconds (Table 8.4 from the seed's inputs,
Eq. 8.14, and the single-bond cycle counts of seed 002); :func:`markdown` turns claims into the table the book
prints. The claims read from stored benchmark studies (DEM identification, grooves, fatigue beam, anisotropic
damage) belong to the source checkout, not to the installed package: ``benchmarks/reproduction.py`` builds them
from ``benchmarks/results`` and adds the ones here.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import wear
from .validation import check_finite, check_range

__all__ = ["Claim", "VERDICTS", "markdown", "recomputed", "verdict"]

VERDICTS = ("reproduced", "close", "differs", "not computed")


@dataclass(frozen=True)
class Claim:
    """One reproduced (or not) result: where in the seed, what, the two values, and the verdict."""

    where: str
    quantity: str
    seed: str
    ours: str
    deviation: str
    verdict: str
    chapter: str


def verdict(deviation: float, close: float = 0.05, reproduced: float = 0.01) -> str:
    """``reproduced`` if ``|deviation|`` ≤ ``reproduced``, ``close`` if ≤ ``close``, else ``differs``.

    ``deviation`` is relative (ours / seed − 1); ``0 ≤ reproduced ≤ close``.
    """
    deviation = check_finite("deviation", deviation)
    close = check_range("close", close, 0.0)
    reproduced = check_range("reproduced", reproduced, 0.0, close)
    return "reproduced" if abs(deviation) <= reproduced else "close" if abs(deviation) <= close else "differs"


def _table_8_4() -> Claim:
    """Table 8.4 recomputed from the seed's printed A_g and f_ab by Eq. (8.14), against its printed rates."""
    table = wear.astm_g65_table()
    off = float(max(abs(table["ours"] - table["seed"])))
    within = off <= 0.5 * wear.TABLE_8_4_RESOLUTION * (1 + 1e-9)
    return Claim("Table 8.4", "wear rates from the seed's A_g, f_ab (Eq. 8.14)", "8.07 … 0.44 × 10⁻⁷ m³/s",
                 f"{table['ours'][0] * 1e7:.2f} … {table['ours'][-1] * 1e7:.2f} × 10⁻⁷ m³/s",
                 f"≤ {off * 1e7:.4f} × 10⁻⁷ (printed digit 0.01)", "reproduced" if within else "differs", "wear")


def _fatigue() -> list[Claim]:
    """Seed 002's constitutive numbers, recomputed (about a second): Fig. 11a and the cycle jump of Sec. 4.1."""
    from .fatigue import BondParameters, cyclic_test

    p = BondParameters()
    cycles = lambda q, **kw: cyclic_test(q, "tension", to_failure=False, **kw).simulated_cycles
    claims = []
    for m, seed in ((0.8, 2008), (1.2, 50)):
        q = p.replace(paris_exponent=m)
        printed, peak = cycles(q), cycles(q, stress_min=0.0)
        claims.append(Claim("seed 002 Fig. 11a", f"cycles D 0.01 → 0.4, m = {m}, ΔK from the printed 20–60 kPa range",
                            str(seed), str(printed), f"{printed / seed - 1:+.0%}", verdict(printed / seed - 1),
                            "fatigue"))
        claims.append(Claim("seed 002 Fig. 11a", f"cycles D 0.01 → 0.4, m = {m}, ΔK from the 60 kPa peak", str(seed),
                            str(peak), f"{peak / seed - 1:+.1%}", verdict(peak / seed - 1), "fatigue"))
    full = cycles(p, stress_min=0.0)
    for jump, seed in ((0.005, 388.8), (0.01, 797.4)):
        ours = 100.0 * full / cycles(p, stress_min=0.0, jump=jump)
        claims.append(Claim("seed 002 Sec. 4.1", f"cycle jump ΔD_jump = {jump}: full / simulated cycles",
                            f"{seed} %", f"{ours:.1f} %", f"{ours / seed - 1:+.1%}", verdict(ours / seed - 1),
                            "fatigue"))
    return claims


def recomputed() -> list[Claim]:
    """The claims the package computes without stored results: Table 8.4 from the seed's inputs (chapter
    ``wear``), then seed 002's single-bond cycle counts and cycle jump (chapter ``fatigue``)."""
    return [_table_8_4(), *_fatigue()]


def markdown(claims: list[Claim]) -> str:
    """The claims as a Markdown table (the book's introduction)."""
    rows = ["| seed | quantity | seed value | ours | deviation | verdict | chapter |", "|---|---|---|---|---|---|---|"]
    rows += [f"| {c.where} | {c.quantity} | {c.seed} | {c.ours} | {c.deviation} | **{c.verdict}** | {c.chapter} |"
             for c in claims]
    return "\n".join(rows)
