"""The package stands alone: a wheel built from the checkout, installed elsewhere, runs every chapter package.

The wheel (``pip wheel --no-deps``, built from a copy of the package's sources so that the checkout gets no
``build/``) is installed with ``pip install --no-deps --target`` into a temporary folder; a fresh interpreter of this
environment (which supplies the dependencies) runs from another temporary folder with only that install on
``PYTHONPATH``. It reaches every chapter package as an attribute of ``abrakit`` and computes one number of each
against its closed form or the seed; ``abrakit demo intro`` prints the reproduction verdicts the package computes
itself, and the README's example prints the output the README shows. Every abrakit module it loads must come from
the install, none from the checkout.
"""

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

#: chapter package -> (what its call computes, largest allowed |deviation|)
TOLERANCES = {
    "tensors": ("Voigt C_1111 / (lambda + 2 mu) - 1", 1e-12),
    "evolution": ("implicit against variational PMDP update, relative", 1e-8),
    "dem": ("two-sphere contact time / pi sqrt(m*/K) - 1", 1e-4),
    "identification": ("E consistent / E published / (4/9) - 1 (Eq. 5.20)", 1e-12),
    "experiments": ("SpecimenSpec keeps its particle count", 0.0),
    "materials": ("elastic stress of the Table 7.1 steel / (E eps) - 1", 1e-9),
    "fem": ("reaction of a stretched unit square / (E A eps) - 1", 1e-9),
    "damage": ("crack-band work to separation / (G_Ic A) - 1", 1e-3),
    "scratch": ("Hertz peak pressure / (3 F / (2 pi a^2)) - 1", 1e-9),
    "wear": ("max |Table 8.4 ours - seed| in 1e-7 m^3/s (printed digit 0.01)", 0.005),
    "g65": ("sand flow / (300 and 400 g/min of quartz at 2650 kg/m^3) - 1, summed", 1e-12),
    "fatigue": ("seed 002 Fig. 11a cycles, m = 1.2, / 50 - 1", 0.0),
}

CHILD = textwrap.dedent('''
    import json
    import math
    import sys
    import traceback

    import numpy as np
    import skfem

    import abrakit


    def tensors(t):
        lam, mu = t.lame(210_000.0, 0.3)
        return t.isotropic_stiffness(210_000.0, 0.3, "voigt")[0, 0] / (lam + 2 * mu) - 1


    def evolution(ev):
        times = np.linspace(0.0, 1.0, 33)
        strain = 2e-3 * np.sin(2 * np.pi * times)
        model, diss = ev.Plasticity1D(E=200_000.0, K=8_000.0), ev.elasto_viscoplastic(60.0, 10_000.0)
        closed, numeric = (ev.simulate(model, strain, times, diss, s) for s in ("implicit", "variational"))
        field = model.initial_state()._fields[0]
        return np.max(np.abs(closed[field] - numeric[field])) / np.max(np.abs(closed[field]))


    def dem(d):
        impact = d.two_sphere_impact(radius=0.01, density=2650.0, kn=1e5, velocity=1.0)
        return impact["duration"] / impact["duration_analytic"] - 1


    def identification(idf):
        rho_c = idf.contact_density(6.0, 0.35, 1e-3)
        published, consistent = (idf.elastic_constants(1e7, 4e6, rho_c, 1e-3, v)[0]
                                 for v in ("published", "consistent"))
        return consistent / published / (4 / 9) - 1


    def experiments(x):
        return x.SpecimenSpec(n_particles=50).n_particles / 50 - 1


    def materials(m):
        p = m.TABLE_7_1
        curve = m.uniaxial_stress(m.VonMisesPlasticity(p["E"], p["nu"], p["r_p"], p["K_H"]), m.ramp(1e-4, 4))
        return curve.stress_component("11")[-1] / (p["E"] * 1e-4) - 1


    def fem(f):
        tags = {"left": lambda x: x[0] < 1e-9, "right": lambda x: x[0] > 1 - 1e-9, "bottom": lambda x: x[1] < 1e-9}
        basis = f.vector_basis(skfem.MeshQuad().refined(2).with_boundaries(tags))
        fixed = [f.Dirichlet(f.boundary_dofs(basis, "left", "x"), 0.0),
                 f.Dirichlet(f.boundary_dofs(basis, "bottom", "y"), 0.0),
                 f.Dirichlet(f.boundary_dofs(basis, "right", "x"), 0.01, name="right")]
        result = f.Solver(basis, abrakit.materials.LinearElastic(1000.0, 0.0), fixed).run(progress=False)
        return abs(result.curves["F_right"][-1]) / 10.0 - 1


    def damage(d):
        bar = d.CrackBandBar(1)
        control = abrakit.fem.StepControl(initial=0.01, maximum=0.01)
        run = bar.solver(follow=False, control=control).run(progress=False)
        v, F = run.curves["u_right"], run.curves["F_right"]
        return float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(v))) / bar.fracture_energy - 1


    def scratch(s):
        assert isinstance(s.ScratchScene, type), "abrakit.scratch.ScratchScene is the chapter's scene"
        c = s.hertz_sphere(210_000.0, 0.3, 0.05, 1e-4)
        return c.max_pressure / (3 * c.force / (2 * math.pi * c.contact_radius**2)) - 1


    def wear(w):
        table = w.astm_g65_table()
        return float(np.max(np.abs(table["ours"] - table["seed"]))) * 1e7


    def g65(g):
        low, high = g.sand_volume_flow()
        return low / (0.300 / 60 / 2650.0) - 1 + high / (0.400 / 60 / 2650.0) - 1


    def fatigue(fa):
        bond = fa.BondParameters().replace(paris_exponent=1.2)
        return fa.cyclic_test(bond, "tension", stress_min=0.0, to_failure=False).simulated_cycles / 50 - 1


    report = {"values": {}, "errors": {}}
    for name in sys.argv[1].split(","):
        try:
            report["values"][name] = float(globals()[name](getattr(abrakit, name)))
        except Exception:
            report["errors"][name] = traceback.format_exc(limit=3)
    report["modules"] = {name: getattr(module, "__file__", None) for name, module in sys.modules.items()
                         if name.split(".")[0] == "abrakit"}
    print(json.dumps(report))
''')


def _run(args, cwd, env, timeout=600):
    return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(install folder, environment, working folder outside the checkout) of a wheel of the checkout."""
    base = tmp_path_factory.mktemp("wheel")
    source = base / "source"
    shutil.copytree(ROOT / "abrakit", source / "abrakit", ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy2(ROOT / name, source / name)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    built = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(base / "dist"), str(source)],
                 base, env)
    assert built.returncode == 0, built.stderr[-2000:]
    wheels = list((base / "dist").glob("abrakit-*.whl"))
    assert len(wheels) == 1, wheels
    target = base / "site"
    done = _run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(target), str(wheels[0])],
                base, env)
    assert done.returncode == 0, done.stderr[-2000:]
    work = base / "elsewhere"
    work.mkdir()
    return target, {**env, "PYTHONPATH": str(target)}, work


def test_the_wheel_holds_the_package_and_nothing_of_the_checkout(installed):
    target, _, _ = installed
    assert (target / "abrakit" / "__init__.py").is_file()
    assert not (target / "benchmarks").exists() and not (target / "tests").exists()
    assert not any(target.glob("abrakit/**/results/*.json"))


def test_every_chapter_package_runs_from_the_installed_wheel(installed):
    target, env, work = installed
    (work / "child.py").write_text(CHILD)
    done = _run([sys.executable, "child.py", ",".join(TOLERANCES)], work, env)
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["errors"] == {}, "\n".join(f"{k}:\n{v}" for k, v in report["errors"].items())
    off = {name: (what, report["values"][name], tolerance) for name, (what, tolerance) in TOLERANCES.items()
           if not abs(report["values"][name]) <= tolerance}
    assert off == {}
    outside = {name: path for name, path in report["modules"].items()
               if path is not None and not Path(path).resolve().is_relative_to(target.resolve())}
    assert outside == {}, f"abrakit modules loaded from outside the install: {outside}"


def test_the_installed_command_prints_the_recomputed_verdicts(installed):
    target, env, work = installed
    done = _run([sys.executable, str(target / "bin" / "abrakit"), "demo", "intro"], work, env)   # the entry point
    assert done.returncode == 0, done.stderr[-3000:]
    assert "reproduced: Table 8.4" in done.stdout and "seed 002 Fig. 11a" in done.stdout
    assert "not computed" not in done.stdout


def test_the_readme_example_prints_what_the_readme_shows(installed):
    _, env, work = installed
    readme = (ROOT / "README.md").read_text()
    code = readme.split("```python\n", 1)[1].split("```", 1)[0]
    shown = readme.split("```text\n", 1)[1].split("```", 1)[0]
    (work / "readme_example.py").write_text(code)
    done = _run([sys.executable, "readme_example.py"], work, env)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout == shown
