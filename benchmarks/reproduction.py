"""What the toolkit reproduces from the seed and how far it is off: one table, from this checkout's stored results.

:func:`status` reads the benchmark results (``benchmarks/results/*.json``), adds the claims the package recomputes
itself (:func:`abrakit.reproduction.recomputed`) and returns one :class:`~abrakit.reproduction.Claim` per figure or
table of the seed, in the order of the chain (DEM identification, scratch, wear), then the fatigue bond and beam and
the anisotropic damage of seed 001. A missing result file gives ``not computed`` with the command that produces it.
:func:`stored_result` is how the book's chapters read one stored result. The book imports this module through
``book/benchmark_results.py``; ``python benchmarks/reproduction.py`` prints the table.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from abrakit import wear
from abrakit.io import read_json
from abrakit.reproduction import VERDICTS, Claim, markdown, recomputed, verdict

__all__ = ["RESULTS", "VERDICTS", "Claim", "markdown", "status", "stored_result"]

RESULTS = Path(__file__).resolve().parent / "results"


def _load(results: Path, name: str):
    path = Path(results) / f"{name}.json"
    return read_json(path) if path.exists() else None


def stored_result(name: str, *, results: str | Path = RESULTS, fallback: bool = True) -> dict | None:
    """The stored result ``<results>/<name>.json`` of ``benchmarks/bench_<name>.py``, for the book's chapters.

    When it is missing, this says so and names the command that produces it; with ``fallback`` (and the
    benchmark script beside the results) it then runs the benchmark's quick mode into a temporary folder and
    returns that result instead, so a chapter still executes (minutes, not the study's hours). Returns ``None``
    when there is neither the file nor a script to run.
    """
    stored = _load(results, name)
    if stored is not None:
        return stored
    script = Path(results).parent / f"bench_{name}.py"
    print(f"{Path(results).name}/{name}.json is missing: `python benchmarks/bench_{name}.py` produces it.")
    if not (fallback and script.is_file()):
        return None
    import subprocess
    import tempfile

    outdir = Path(tempfile.mkdtemp(prefix=f"abrakit_{name}_"))
    print(f"Running its quick mode now (`python benchmarks/bench_{name}.py --quick`) into {outdir}; the numbers "
          "below come from that smaller study.", flush=True)
    subprocess.run([sys.executable, str(script), "--quick", "--outdir", str(outdir)], check=True,
                   cwd=script.parent, stdout=subprocess.DEVNULL)
    for candidate in (f"{name}_quick.json", f"{name}.json"):
        if (outdir / candidate).exists():
            return read_json(outdir / candidate)
    raise FileNotFoundError(f"bench_{name}.py --quick wrote no {name}.json into {outdir}")


def _missing(where, quantity, seed, chapter, script) -> Claim:
    return Claim(where, quantity, seed, f"run `python benchmarks/{script}`", "—", "not computed", chapter)


def _table_8_4_from_grooves(results: Path) -> list[Claim]:
    steady = _load(results, "scratch_steady")
    if steady is None:
        return [_missing("Table 8.4", "wear rates from our own grooves", "8.07 … 0.44 × 10⁻⁷ m³/s",
                         "scratch_to_wear", "bench_scratch_steady.py --stored-only")]
    claims = []
    readings = [("table_8_4", "from_sections", "finite strain, F-bar, groove sections of 200 µm slides"),
                ("table_8_4_steady", "from_steady_rates", "finite strain, F-bar, steady rates of 400 µm slides")]
    for key, column, how in readings:
        if key not in steady:
            continue
        t = steady[key]
        ratios = [ours / printed for ours, printed in zip(t[column], t["seed_printed"], strict=True)]
        claims.append(Claim("Table 8.4", f"wear rates from our grooves ({how})", "8.07 … 0.44 × 10⁻⁷ m³/s",
                            f"{t[column][0] * 1e7:.2f} … {t[column][-1] * 1e7:.2f} × 10⁻⁷ m³/s",
                            f"×{min(ratios):.2f} … ×{max(ratios):.2f}", "differs", "scratch_to_wear"))
    return claims


def _grains(results: Path) -> list[Claim]:
    steady = _load(results, "scratch_steady")
    claims = []
    for label, grain, key in (("D = 100 µm", wear.GRAIN_100UM, "grain_100um"),
                              ("D = 200 µm", wear.GRAIN_200UM, "grain_200um")):
        if steady is None or key not in steady.get("grains_at_2N", {}):
            claims.append(_missing("Sec. 8.2", f"groove of a {label} grain at 2 N", f"A_g {grain.A_g * 1e12:g} µm²",
                                   "scratch_to_wear", "bench_scratch_steady.py --stored-only"))
            continue
        g = steady["grains_at_2N"][key]
        spread = steady.get("mesh_spread", {}).get(str(round(grain.D * 1e6)))   # of the grain's run nearest 2 N
        rates = f"{g['f_ab_rates']:.2f}" + (f" ± {spread['spread']['f_ab_rates']:.3f} over {len(spread['levels'])} "
                                           "meshes" if spread and len(spread["levels"]) > 1 else "")
        dev = g["A_g_um2"] / (grain.A_g * 1e12) - 1.0
        claims.append(Claim("Sec. 8.2", f"groove area A_g, {label} grain at 2 N", f"{grain.A_g * 1e12:g} µm²",
                            f"{g['A_g_um2']:.1f} µm²", f"{dev:+.0%}", verdict(dev, close=0.15), "scratch_to_wear"))
        ours, f_ab = f"{g['f_ab']:.2f} (sections), {rates} (rates)", g["f_ab"]
        settled = steady.get("grains_steady", {}).get(key)
        if settled is not None and math.isfinite(settled["f_ab_rates"]):   # the grain's defined f_ab (400 µm slides)
            ours = f"{settled['f_ab_rates']:.2f} steady (400 µm slides); 200 µm slides: {ours}"
            f_ab = settled["f_ab_rates"]
        claims.append(Claim("Sec. 8.2", f"degree of wear f_ab, {label} grain", f"{grain.f_ab:g}", ours,
                            f"{f_ab - grain.f_ab:+.2f}", verdict(f_ab / grain.f_ab - 1.0, close=0.15),
                            "scratch_to_wear"))
    return claims


def _elastic(results: Path) -> list[Claim]:
    data = _load(results, "experiments_elastic")
    if data is None:
        return [_missing("Figs. 5.6a, 5.7a", "E of DEM specimens against Eq. (5.20)", "≈ 1", "dem_identification",
                         "bench_experiments_elastic.py")]
    claims = []
    for kind, figure, scheme in (("granular", "Fig. 5.7a", "sphere"), ("bonded", "Fig. 5.6a", "wall")):
        sizes = data["elastic"][kind]["sizes"]
        largest = max(sizes, key=int)
        entry = sizes[largest]
        published = entry[f"ratio_E_{scheme}_published"]["mean"]
        consistent = entry[f"ratio_E_{scheme}_consistent"]["mean"]
        claims.append(Claim(figure, f"E of {kind} specimens / Eq. (5.20) ({scheme}-based, N = {largest})", "≈ 1",
                            f"{published:.2f} (published form), {consistent:.2f} (consistent form)",
                            f"{published - 1.0:+.0%}", verdict(published - 1.0, close=0.15), "dem_identification"))
    return claims


def _beam(results: Path) -> list[Claim]:
    data = _load(results, "fatigue_beam")
    if data is None:
        return [_missing("seed 002 Sec. 5.2", "flexural strength FS_max of the beam", "1336.4 kPa",
                         "four_point_bending", "bench_fatigue_beam.py")]
    claims = []
    for grading, label in (("lattice", "lattice"), ("fuller", "Fuller-graded packing")):
        rows = [r for r in data["resolution"] if r.get("grading", "lattice") == grading]
        if not rows:
            continue
        finest = min(r["radius"] for r in rows)
        values = [r["FS_max"] / 1e3 for r in rows if r["radius"] == finest]
        mean = sum(values) / len(values)
        claims.append(Claim("seed 002 Sec. 5.2", f"flexural strength FS_max ({label}, largest radius "
                            f"{finest * 1e3:g} mm, {len(values)} samples)", "1336.4 kPa", f"{mean:.0f} kPa",
                            f"{mean / 1336.4 - 1:+.0%}", verdict(mean / 1336.4 - 1), "four_point_bending"))
    runs = {r.get("name"): r for r in data.get("jump", [])}
    reference, paper = runs.get("reference"), runs.get("frozen_0.003")
    if reference and paper and reference["life"] and paper["life"]:
        deviation = paper["life"] / reference["life"] - 1
        claims.append(Claim("seed 002 Sec. 5.2", "fatigue life at 77 % with ΔD_jump = 0.003 against cycle by cycle",
                            "a 'marginal' effect", f"{paper['life']} against {reference['life']} cycles",
                            f"{deviation:+.0%}", verdict(deviation), "four_point_bending"))
    return claims


def _anisotropic(results: Path) -> list[Claim]:
    data = _load(results, "anisotropic_damage")
    if data is None:
        return [_missing("seed 001", "energy per crack area = G_Ic; damage against LEFM", "G_Ic; LEFM",
                         "anisotropic_damage", "bench_anisotropic_damage.py")]
    bars = [r for r in data["rows"] if r["study"] == "bar"]
    worst = max(abs(r["max_error_pct"]) for r in bars) / 100
    claims = [Claim("seed 001", f"energy per crack area, bar of {min(r['elements'] for r in bars)}–"
                    f"{max(r['elements'] for r in bars)} elements", "G_Ic (area of the softening law)",
                    f"G_Ic within {worst:.2%}", f"≤ {worst:.2%}", verdict(worst), "anisotropic_damage")]
    dcb = [r for r in data["rows"] if r["study"] == "dcb"]
    if dcb:
        finest = min(dcb, key=lambda r: (r["size"], float(r["case"].split()[2])))   # finest mesh, widest zone
        claims.append(Claim("seed 001 (Nairn 2018)", f"DCB propagation force against LEFM ({finest['case']}: the "
                            "finest mesh, the best-resolved process zone)",
                            "damage = fracture mechanics with the right parameters",
                            f"{finest['error_pct']:+.1f} % mean above LEFM", f"{finest['error_pct']:+.1f} %",
                            verdict(finest["error_pct"] / 100), "anisotropic_damage"))
    return claims


def status(results: str | Path = RESULTS) -> list[Claim]:
    """Every claim, in the order of the chain (DEM identification, scratch, wear), then the fatigue bond and beam, and
    the anisotropic damage of seed 001."""
    results = Path(results)
    package = recomputed()
    by_chapter = lambda chapter: [c for c in package if c.chapter == chapter]
    return [*_elastic(results), *_grains(results), *by_chapter("wear"), *_table_8_4_from_grooves(results),
            *by_chapter("fatigue"), *_beam(results), *_anisotropic(results)]


if __name__ == "__main__":
    print(markdown(status(sys.argv[1] if len(sys.argv) > 1 else RESULTS)))
