"""Fuzz the public API with invalid input, starting from calls the test suite makes.

Two stages:

1. **harvest** runs the test suite (not the slow studies) with a profiler hook and keeps, for every public function
   and class of ``abrakit`` (module level, name without a leading underscore), up to ``PER_CALLABLE`` calls whose
   arguments are plain data: numbers, strings, ``None``, numpy arrays, tuples, lists and dicts of these, and
   abrakit dataclasses made of them. They are pickled into ``tools/api_calls.pkl``: valid calls, by construction.
2. **fuzz** replays each valid call (its result must hold no NaN or infinity) and then the same call with one
   numeric argument made invalid: NaN for a number, a NaN entry for an array, a string for a number, ``None`` where
   neither the default (``None``) nor the annotation (``... | None``) allows it. Every outcome falls in one class
   (:data:`OUTCOMES`):

   - ``named``: ``ValueError``/``TypeError`` whose message names the parameter (what the toolkit promises);
   - ``unnamed``: ``ValueError``/``TypeError`` that does not name it;
   - ``deep``: another exception, e.g. from inside numpy or scipy;
   - ``non_finite``: the call returned NaN or infinity;
   - ``accepted``: the call returned a finite result for the invalid input;
   - ``timeout``: the call ran longer than its limit (a study that an invalid input sent astray).

   Some arguments accept NaN by design (curves written as they come, statistics that count what they drop):
   :data:`NAN_ALLOWED` lists them with the reason.

3. **faces**: the callables a chapter face lists (``abrakit.<chapter>.__all__``, :func:`face_callables`) are the
   door the toolkit promises to guard. :func:`face_report` says for each whether it has a valid call (harvested,
   or written by hand in :data:`HAND_CALLS` for names the tests never call with plain data), and their valid calls
   get three more invalid values: ``+inf`` (an infinite entry of an array) where a finite value is meant, and, for
   a parameter that must be positive (:func:`must_be_positive`: :data:`POSITIVE_NAME`, :data:`POSITIVE`), zero and
   a negative value. A NaN or infinity returned for *finite* bad input (zero, negative, a string, None) is counted
   apart, as ``non_finite_from_finite``. Values that a call rightly takes are listed in :data:`ALLOWED` with the
   reason (an infinite limit that means "none", a coordinate that may be negative, ...).

``python tools/api_fuzz.py harvest [--merge] [tests ...]`` then ``python tools/api_fuzz.py fuzz`` writes the counts to
``benchmarks/results/api_fuzz.json``; ``tests/test_api_fuzz.py`` runs the fuzz stage on the stored calls.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import inspect
import pickle
import pkgutil
import re
import signal
import sys
import time
import warnings
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
CATALOGUE = ROOT / "tools" / "api_calls.pkl"
PER_CALLABLE = 3
MAX_ARRAY = 20_000
MAX_BYTES = 10_000         # a harvested call's pickled arguments: larger ones (whole meshes, long curves) are dropped
SLOW_CALL = 0.5            # s: valid calls slower than this are not fuzzed (a study, not an input check)
OUTCOMES = ("named", "unnamed", "deep", "non_finite", "accepted", "timeout")

#: (callable, parameter) pairs that take NaN on purpose, and why.
NAN_ALLOWED = {
    ("abrakit.experiments.closed_form_checks.mean_interval", "values"): "NaN samples are dropped and counted "
                                                                        "(``dropped``)",
    ("abrakit.io.jsonable", "obj"): "results hold NaN where a quantity is undefined; strict JSON writes it as the "
                                    "string \"NaN\"",
    ("abrakit.io.strict_json", "data"): "the same: NaN and infinities become the strings NaN, Infinity, -Infinity",
    ("abrakit.io.from_strict_json", "data"): "the inverse: the strings come back as NaN and infinities",
    ("abrakit.validation.check_shape", "array"): "a shape check returns the array as given; its values are the "
                                                 "business of check_finite",
    ("abrakit.validation.all_finite", "arr"): "it answers whether an array holds NaN or infinity",
}

#: Modules of input checks: their ``name`` argument is the parameter their errors must name (``check_range("x",
#: None)`` says "x must be ..."), so an error naming it is named.
VALIDATORS = re.compile(r"^abrakit\.validation$")

#: Records and state containers the toolkit builds and returns: their fields are outputs, checked where they are
#: computed, and the functions users call to make them (``Particles.spheres``, ``genesis``, ...) check their input.
RECORDS = {
    "abrakit.damage.localisation.BarRun", "abrakit.damage.metrics.BandWidth", "abrakit.dem.bonds.ParallelBonds",
    "abrakit.dem.clumps.Clumps", "abrakit.dem.simulation.EnergyAccount", "abrakit.dem.state.Particles",
    "abrakit.experiments.compression.CompressionCurve", "abrakit.experiments.specimen.Specimen",
    "abrakit.fem.pathfollow.PathPoint", "abrakit.fem.problems.ThickCylinderSolution",
    "abrakit.materials.base.MaterialResponse", "abrakit.materials.plasticity.PlasticStep",
    "abrakit.dem.neighbours.VerletList",
    # what the chapter runs return (their fields are results) and the specimens they build
    "abrakit.damage.model_two_fe.ModelTwoResult", "abrakit.damage.runs.SpecimenRun",
    "abrakit.damage.specimens.DamageSpecimen", "abrakit.experiments.specimen.DemSpecimen",
    "abrakit.scratch.run.ScratchResult", "abrakit.scratch.scene.ScratchSpecimen",
    "abrakit.scratch.groove.GrooveMetrics",
    "abrakit.scratch.readouts.GrooveBalance", "abrakit.scratch.run_hertz.HertzCheck",
    # the interface every material implements: abstract, built only through a model (LinearElastic, ...)
    "abrakit.materials.base.Material",
}

#: Callables whose valid calls may return a non-finite value, documented in their docstrings, and why.
NON_FINITE_BY_DESIGN = {
    "abrakit.damage.metrics.softening_displacement": "inf when the force never falls to the fraction (no drop)",
    "abrakit.experiments.closed_form_checks.mean_interval": "std and half-width of a single value are undefined "
                                                            "(NaN, as numpy's sample std)",
    "abrakit.experiments.compression.crack_initiation_stress": "NaN when no bond broke in the test",
    "abrakit.experiments.cyclic.stage_slopes": "NaN for a stage with fewer than two distinct points (docstring)",
    "abrakit.io.loads": "strict JSON's strings NaN, Infinity, -Infinity are read back as the numbers they stand for",
}


#: Parameter names that denote a quantity that must be positive (a radius, a thickness, a modulus, a number of steps
#: or of cycles, a time step, a size): zero and a negative value are invalid for them. Matched against the whole
#: name; :data:`POSITIVE` adds parameters the pattern misses, :data:`NOT_POSITIVE` removes ones it catches wrongly.
POSITIVE_NAME = re.compile(
    r"^(?:\w+_)?(?:radius|radii|thickness|modulus|moduli|diameter|density|steps|cycles|count|dt|time_step|size|"
    r"sizes|length|height|mass|volume|life|stiffness|rpm|E|youngs?)$")

#: (callable, parameter) that must be positive though their names do not say so.
POSITIVE = {
    ("abrakit.materials.strength_statistics.weibull_cdf", "shape"),
    ("abrakit.materials.strength_statistics.normal_cdf", "cv"),
}

#: (callable, parameter) the name pattern catches though zero or a negative value is valid, and why.
NOT_POSITIVE = {
    ("abrakit.dem.measure.relax", "min_steps"): "a lower bound of the steps: 0 lets relax stop at its first check",
}

#: (callable, parameter, label) whose "invalid" value is valid for that call, and why (labels of
#: :func:`invalid_values` and :func:`face_invalid_values`: "nan", "string", "none", "+inf", "zero", ...).
ALLOWED = {
    **{("abrakit.experiments.disk_packing.fuller_passing", "radius", label): "the sieve size is clipped to the "
       "grading: the fraction finer than r <= r_min is 0, finer than r >= r_max (also +inf) is 1"
       for label in ("+inf", "inf entry", "zero", "negative")},
    **{("abrakit.identification.isotropic_part", "stiffness", label): "the projection is defined for any finite 6x6 "
       "matrix: one entry (C11 here) of zero or either sign is a matrix to project, not a wrong input"
       for label in ("zero", "negative")},
    **{("abrakit.identification.series_stiffness", k, label): "documented: inf is a rigid side, K is the other "
       "side's stiffness (Eq. 4.11: k_a k_b / (k_a + k_b) -> k_b)"
       for k in ("k_a", "k_b") for label in ("+inf", "inf entry")},
    **{(f"abrakit.scratch.hertz.{name}", "E_indenter", label): "documented: E_indenter = inf is a rigid indenter "
       "(the default), E* = E / (1 - nu^2)" for name in ("hertz_sphere",)
       for label in ("+inf", "inf entry")},
    ("abrakit.dem.scenes.dense_packing", "seed", "none"): "numpy's default_rng(None): a packing from fresh entropy",
    ("abrakit.wear.wheel_surface_speed", "rpm", "zero"): "documented n >= 0: a wheel at rest has surface speed 0",
    ("abrakit.scratch.erosion.Erosion", "length", "zero"): "documented: a nonlocal length of 0 is local erosion "
    "(each element's own damage), which the coarse demo scenes use",
}


def _hand_calls() -> dict[str, list[dict]]:
    """Valid calls of face callables that the test suite never calls with plain data (built here: some need a mesh
    or a callable, which the catalogue does not store)."""
    import skfem

    bar = skfem.MeshLine(np.linspace(0.0, 10.0, 11))
    calls = {
        "abrakit.tensors.sphere_average": [{"f": lambda n: n[:, :, None] * n[:, None, :], "degree": 4}],
        "abrakit.experiments.cyclic.stage_slopes": [
            {"measured_at": np.arange(0.0, 101.0, 5.0), "modulus_ratio": 1.0 - 0.002 * np.arange(0.0, 101.0, 5.0),
             "life": 100.0, "bounds": (0.1, 0.9)}],
        "abrakit.materials.strength_statistics.normal_cdf": [{"r": np.array([0.8, 1.0, 1.2]), "cv": 0.2}],
        "abrakit.materials.strength_statistics.weibull_cdf": [
            {"r": np.array([0.5, 1.0, 1.5]), "shape": 6.0, "V0": 1.0, "Vp": 2.0}],
        "abrakit.materials.strength_statistics.truncated_cdf": [
            {"cdf": lambda r: 0.5 * np.ones_like(r), "r": np.array([0.5, 1.0])}],
        "abrakit.wear.penetration_regime": [{"D_p": 0.15}, {"D_p": np.array([0.05, 0.25, 0.4])}],
        "abrakit.g65.G65Standard": [{"wheel_diameter": 0.2286, "wheel_width": 0.0127, "rubber_shore_a": (58.0, 62.0),
                                     "rubber_poisson": 0.5, "rpm": 200.0, "sand_sizes": (212e-6, 300e-6),
                                     "sand_flow": (5e-3, 6.7e-3), "sand_density": 2650.0,
                                     "coupon": (0.0254, 0.0762, 0.0127), "procedure_b_threshold": 1e-7,
                                     "measured_losses": (1e-8, 1e-6)}],
        "abrakit.g65.grain_forces": [{"D": 256e-6, "force": 130.0}],
        "abrakit.g65.balanced_loss": [{"D": 256e-6, "hardness": 3.23e9, "removal": lambda D_p: np.zeros_like(D_p),
                                       "procedure": "A"}],
        "abrakit.materials.ductile_failure.JohnsonCookFailure": [
            {"D1": 0.05, "D2": 3.44, "D3": -2.12, "cutoff": -1.0 / 3.0, "minimum_strain": 0.01}],
        "abrakit.scratch.erosion.Erosion": [{"length": 0.001, "residual": 1e-6}],
        "abrakit.evolution.PlasticState": [{"eps_p": np.zeros(3), "alpha": np.zeros(3)}],
        "abrakit.damage.localisation.cross_section": [
            {"mesh": bar, "area": 100.0, "depth": 0.05, "width": 1.0, "notch": 0.02}],
        "abrakit.damage.model_two_fe.default_material": [{"alpha": 0.05}],
    }
    # ---- built objects: meshes, bases, materials, a small packing ------------------------------------------------
    from abrakit.dem.clumps import dyad
    from abrakit.dem.scenes import dense_packing
    from abrakit.evolution import Plasticity1D, rate_independent
    from abrakit.fatigue import BondParameters
    from abrakit.fem.kinematics import Kinematics, vector_basis
    from abrakit.materials import LinearElastic, VonMisesPlasticity
    from abrakit.materials.driver import ramp
    from abrakit.scratch.contact import initial_state

    square = skfem.MeshQuad().refined(2)
    calls["abrakit.damage.metrics.band_width"] = [
        {"mesh": square, "values": np.linspace(0.0, 1.0, square.t.shape[1]), "threshold": 0.5}]
    basis = vector_basis(square)
    elastic = LinearElastic(1000.0, 0.3)
    plastic = VonMisesPlasticity(1000.0, 0.3, 10.0, 100.0)
    packing = dense_packing(27, seed=0, agitation=0.0, walls=True)
    tracked = dense_packing(8, seed=0, agitation=0.0, walls=True, track_energy=True)
    tracked.run(2)
    eps = np.array([1e-3, 0.0, 0.0, 0.0, 0.0, 0.0])
    from abrakit import evolution
    from abrakit.damage.localisation import bar_mesh
    from abrakit.fem import Dirichlet
    from abrakit.materials import ModelIDamage

    tagged = vector_basis(skfem.MeshQuad().refined(2).with_boundaries(
        {"left": lambda x: x[0] == 0.0, "bottom": lambda x: x[1] == 0.0, "right": lambda x: x[0] == 1.0}))
    pulled = [Dirichlet.on(tagged, "left", "x"), Dirichlet.on(tagged, "bottom", "y"),
              Dirichlet.on(tagged, "right", "x", 1e-3, name="end")]
    bar = vector_basis(bar_mesh(5, 2.0))
    bar_pulled = [Dirichlet.on(bar, "left", "x"), Dirichlet.on(bar, "bottom", "y"),
                  Dirichlet.on(bar, "right", "x", 1e-3, name="end")]
    damage = ModelIDamage(1000.0, 0.0, 0.05, beta=1.0)
    return {
        **calls,
        "abrakit.fem.solver.Solver": [{"basis": tagged, "material": elastic, "dirichlet": pulled}],
        "abrakit.fem.pathfollow.PathFollowingSolver": [{"basis": tagged, "material": elastic, "dirichlet": pulled,
                                                        "method": "dissipation", "path": None, "opening": None}],
        "abrakit.fem.problems.thick_cylinder_problem": [{"material": elastic, "n_radial": 4, "n_angular": 4}],
        "abrakit.fem.problems.plate_with_hole_problem": [{"material": elastic, "n_angular": 4, "n_radial": 4}],
        "abrakit.damage.model_one_fe.ModelISolver": [{"basis": bar, "material": damage, "dirichlet": bar_pulled}],
        "abrakit.damage.model_one_path.ModelIPathFollowingSolver": [
            {"basis": bar, "material": damage, "dirichlet": bar_pulled}],
        "abrakit.damage.specimens.specimen": [{"name": "sharp_notch", "level": "coarse"}],
        "abrakit.evolution.variational_update": [
            {"free_energy": lambda e, l: l**2, "dissipation": evolution.elasto_viscoplastic(0.05, 0.05),
             "eps": 0.0, "lam_m": 0.0, "dt": 1.0}],
        "abrakit.dem.scenes.rolling_sphere": [{"friction": 0.9, "velocity": 0.2}],
        "abrakit.fatigue.single_bond.cyclic_test": [
            {"p": BondParameters(), "mode": "tension", "to_failure": False, "max_cycles": 3}],
        "abrakit.fem.kinematics.vector_basis": [{"mesh": square, "element": None, "intorder": None}],
        "abrakit.fem.kinematics.Kinematics": [dict(vars(Kinematics.from_basis(basis)))],
        "abrakit.fem.assembly.Assembler": [{"kinematics": Kinematics.from_basis(basis)}],
        "abrakit.fem.assembly.skfem_tangent": [
            {"basis": basis, "tangent": np.broadcast_to(elastic.stiffness if hasattr(elastic, "stiffness") else
                                                        np.eye(6), (*basis.dx.shape, 6, 6)).copy()}],
        "abrakit.fem.boundary.boundary_dofs": [
            {"basis": vector_basis(square.with_boundaries({"left": lambda x: x[0] == 0.0})), "boundary": "left",
             "components": "x"}],
        "abrakit.fem.meshes.check_quality": [{"mesh": square, "max_aspect_ratio": 20.0, "min_jacobian_ratio": 0.2}],
        "abrakit.fem.linsolve.DirectSolver": [{"backend": "auto", "order": None, "check_tol": 1e-8, "refinements": 2,
                                               "precision": "double", "forcing": 0.0, "krylov_iterations": 8}],
        "abrakit.damage.laplacian.face_neighbours": [{"mesh": square}],
        "abrakit.damage.laplacian.element_laplacian": [{"mesh": square, "max_condition": 1e4, "selection": "auto",
                                                        "max_candidates": 16, "monotone": True}],
        "abrakit.damage.model_two_fe.rate_limit_work": [
            {"u": np.array([0.0, 1e-3, 2e-3]), "u_old": np.array([0.0, 5e-4, 1e-3]),
             "reactions_old": np.array([1.0, 2.0, 3.0]), "prescribed": np.array([0, 2]), "force_scale": 1.0}],
        "abrakit.materials.driver.uniaxial_stress": [{"material": plastic, "eps11": ramp(2e-2, 4)}],
        "abrakit.materials.driver.uniaxial_strain": [{"material": plastic, "eps11": ramp(2e-2, 4)}],
        "abrakit.materials.driver.pure_shear": [{"material": plastic, "gamma12": ramp(2e-2, 4)}],
        "abrakit.materials.driver.plane_strain_tension": [{"material": plastic, "eps11": ramp(2e-2, 4)}],
        "abrakit.materials.base.finite_difference_tangent": [
            {"material": elastic, "state": elastic.initial_state(()), "eps": eps, "h": 1e-8, "dt": 1.0}],
        "abrakit.evolution.simulate": [
            {"model": Plasticity1D(E=1000.0, K=100.0), "strain": np.linspace(0.0, 2e-2, 9),
             "time": np.linspace(0.0, 1.0, 9), "dissipation": rate_independent(10.0), "scheme": "implicit",
             "state0": None}],
        "abrakit.dem.measure.porosity": [{"sim": packing, "volume": 1e-6}],
        "abrakit.dem.measure.coordination_number": [{"sim": packing, "mechanical": False}],
        "abrakit.dem.measure.contact_counts": [{"sim": packing}],
        "abrakit.dem.measure.energy_balance": [{"sim": tracked}],
        "abrakit.dem.measure.unbalanced_force_ratio": [{"sim": packing}],
        "abrakit.dem.measure.relax": [{"sim": packing, "tolerance": 0.5, "stress_tolerance": 0.5, "min_steps": 0,
                                       "max_steps": 10, "check_every": 10}],
        "abrakit.experiments.compression.force_carrying_contacts": [{"sim": packing}],
        "abrakit.dem.bonds.install_contact_bonds": [
            {"sim": packing, "normal_strength": 1e6, "shear_strength": 1e6, "gap": None, "pairs": None}],
        "abrakit.dem.periodic.Periodic": [{"lengths": np.array([1.0, 1.0, 1.0]), "lower": np.zeros(3),
                                           "tilt": np.zeros((3, 3))}],
        "abrakit.dem.clumps.clump_particles": [{"centres": np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0]]),
                                                "template": dyad(0.002), "density": 2650.0, "rng": None}],
        "abrakit.dem.scenes.dense_packing": [{"n": 8, "seed": 0, "radius": 0.001, "spread": 0.1, "overlap": 0.005,
                                              "density": 2650.0, "kn": 1e6, "friction": 0.5, "wall_friction": 0.0,
                                              "agitation": 0.01, "law": None, "walls": True,
                                              "track_energy": False}],
        "abrakit.experiments.specimen.DemMaterial": [
            {"youngs_modulus": 7e10, "stiffness_ratio": 2.5, "friction": 0.5, "density": 2630.0,
             "bond_normal_strength": None, "bond_shear_strength": None, "bond_gap": 1e-3}],
        "abrakit.scratch.contact.contact_response": [
            {"gap": np.array([-1e-4, 1e-4]), "normal": np.array([[0.0, -1.0, 0.0], [0.0, -1.0, 0.0]]),
             "increment": np.ones((2, 3)) * 1e-6, "state": initial_state(2), "c_N": 2.1e8, "c_T": None, "mu": 0.1,
             "normal_gradient": None, "held_direction": None}],
        "abrakit.fatigue.single_bond.BondTest": [{"p": BondParameters(), "mode": "shear"}],
        "abrakit.fatigue.single_bond.monotonic_test": [
            {"p": BondParameters(), "mode": "tension", "increment": 2e-6, "until_damage": 0.9, "max_steps": 2000,
             "test": None}],
        **_study_calls(),
    }


def _square_case(params: dict) -> dict:
    """A sweep case for the hand calls of :func:`abrakit.experiments.run_sweep`: the square of ``x``."""
    return {"square": params["x"] ** 2}


def _study_calls() -> dict[str, list[dict]]:
    """Valid calls of the face's studies and of the readouts of their results, each on a specimen small enough to
    run in a fraction of a second (a few elements, a few particles, a few steps)."""
    import math
    import tempfile

    import matplotlib.pyplot  # noqa: F401 - imported here, plot_field's valid call times the plot, not the import

    from abrakit.damage.localisation import bar_models
    from abrakit.damage.specimens import double_notched, sharp_notch
    from abrakit.dem import Particles, Periodic, Simulation, Walls
    from abrakit.dem.fatigue_specimen import bonded_bar
    from abrakit.evolution import Plasticity1D, elasto_viscoplastic
    from abrakit.experiments.bending import BeamSpec, four_point_beam
    from abrakit.experiments.specimen import SpecimenSpec, genesis
    from abrakit.experiments.sweeps import run_sweep
    from abrakit.fatigue import BondParameters
    from abrakit.scratch.run import run_scratch
    from abrakit.scratch.scene import ScratchScene, SpecimenMesh

    radius, kn = 0.01, 1e6                          # 27 spheres on a simple cubic lattice in a periodic cell
    g = (np.arange(3) + 0.5) * 2 * radius
    x = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    cell = Simulation(Particles.spheres(x, radius, kn=kn, friction=0.5), periodic=Periodic([6 * radius] * 3),
                      local_damping=0.7)
    cell.strain_cell(-1e-3)
    cell.step()
    r, squeeze = 1e-3, 1e-6                         # 64 touching spheres in a box whose walls touch them
    x = r + np.stack(np.meshgrid(*[np.arange(4)] * 3, indexing="ij"), -1).reshape(-1, 3) * 2 * r * (1 - squeeze)
    lattice = Simulation(Particles.spheres(x, r, kn=kn, friction=0.5), track_energy=False,
                         walls=Walls.box(np.full(3, r * squeeze), x.max(axis=0) + r * (1 - squeeze)))
    lattice.run(1, progress=False)
    bar, _, loaded = bonded_bar(BondParameters(), columns=3, rows=1)
    sweeps = Path(tempfile.mkdtemp(prefix="abrakit_fuzz_sweep_"))
    run_sweep(_square_case, [{"x": 1}, {"x": 2}], sweeps, backend="serial")
    strip, notch = double_notched(50), sharp_notch(100)
    u = np.linspace(0.0, 1.0, 11)
    scene = ScratchScene(depth=0.0008, slide=0.004, unload=False, size=(0.06, 0.015, 0.08), indent_steps=1,
                         mesh=SpecimenMesh(h=0.004, h_z=0.005, h_y=0.0015, growth=1.8, width=1.6),
                         kinematics="small", bbar=False, material="elastic")
    scratched = run_scratch(scene, vtu_every=0)
    with warnings.catch_warnings():                 # 20 grains, barely consolidated: a valid call, not a study
        warnings.simplefilter("ignore")
        grains = genesis(SpecimenSpec(n_particles=20, seed=2, aspect=1.0), cache=False, max_steps=300)
    return {
        "abrakit.damage.localisation.localisation_study": [
            {"n_elements": (3, 5), "models": {"local": bar_models()["local"]}, "step": 0.01}],
        "abrakit.damage.metrics.mesh_study": [
            {"curves": {"coarse": (u, 1.1 * np.sin(np.pi * u)), "fine": (u, np.sin(np.pi * u))}, "fields": None,
             "threshold": 0.5, "length": None, "mirror": 1.0}],
        "abrakit.damage.metrics.specimen_metrics": [
            {"specimen": notch, "u": np.array([0.0, 1.0, 2.0, 3.0]), "F": np.array([0.0, 10.0, 6.0, 0.0]),
             "stiffness_loss": np.linspace(0.0, 1.0, notch.elements), "threshold": 0.5}],
        "abrakit.damage.model_two_fe.run_model_two": [{"specimen": strip, "alpha": 0.05, "steps": 3, "end": 0.1}],
        "abrakit.damage.runs.run_specimen": [
            {"specimen": strip, "model": "I", "parameter": 1.0, "step": 0.05, "stop_fraction": 0.5}],
        "abrakit.damage.specimens.plot_field": [
            {"specimen": notch, "values": np.linspace(0.0, 1.0, notch.elements), "colorbar": False}],
        "abrakit.dem.fatigue_specimen.cyclic_bar": [
            {"sim": bar, "loaded": loaded, "stress_min": 20e3, "stress_max": 60e3, "target_damage": 0.4,
             "ramp_steps": 20, "max_cycles": 2}],
        "abrakit.dem.network.network_stiffness": [{"sim": cell}],
        "abrakit.dem.periodic.elastic_probe": [{"sim": cell, "strain": 1e-6, "max_steps": 200, "tol": 1e-6}],
        "abrakit.evolution.convergence_study": [
            {"model": Plasticity1D(E=1000.0, K=100.0), "dissipation": elasto_viscoplastic(10.0, 1.0),
             "strain_fn": lambda t: 2e-2 * np.sin(t), "t_end": 1.0, "n_steps": (4, 8), "schemes": ("implicit",)}],
        "abrakit.experiments.bending.monotonic_bending": [
            {"beam": four_point_beam(BeamSpec(radius=5e-3)), "speed": 5e-4, "max_deflection": 1e-8,
             "record_every": 50, "max_steps": 200}],
        "abrakit.experiments.closed_form_checks.contact_statistics": [{"sim": lattice, "margin": 0.5}],
        "abrakit.experiments.contacting.contact_census": [{"sim": lattice, "wall_zone": 0.0, "tol": 1e-9}],
        "abrakit.experiments.cyclic.cyclic_bending": [
            {"beam": four_point_beam(BeamSpec(radius=5e-3), control="force"), "load_max": 10.0,
             "steps_per_cycle": 50, "max_cycles": 1, "reference_cycles": 1, "max_simulated": 1,
             "quasi_static_check": False}],
        "abrakit.experiments.compression.elastic_test": [
            {"specimen": grains, "crossings": 2.0, "records": 5, "tolerance": 1e-2}],
        "abrakit.experiments.specimen.genesis": [
            {"spec": SpecimenSpec(n_particles=20, seed=2, aspect=1.0), "cache": False, "max_steps": 300}],
        "abrakit.experiments.sweeps.load_sweep": [{"results_dir": sweeps}],
        "abrakit.experiments.sweeps.run_sweep": [
            {"case_fn": _square_case, "params_list": [{"x": 1}, {"x": 2}], "results_dir": sweeps,
             "backend": "serial", "n_jobs": 1}],
        "abrakit.scratch.readouts.groove_balance": [{"result": scratched, "z": scratched.scene.z_section}],
        "abrakit.scratch.run.run_scratch": [{"scene": scene, "vtu_every": 0, "checkpoint_every": 10}],
        "abrakit.scratch.run_hertz.hertz_indentation": [
            {"h": 2 * math.sqrt(0.05 * 5e-4), "penalty": 3.0, "R": 0.05, "d": 5e-4, "steps": 1, "extent": 8.0,
             "growth": 1.8}],
    }


#: Callables with a valid call written by hand (:func:`_hand_calls`), filled by :func:`load_catalogue`.
HAND_NAMES: set[str] = set()

#: Labels of invalid values that are finite: a NaN or infinity returned for them is ``non_finite_from_finite``.
FINITE_LABELS = ("string", "none", "zero", "negative")
#: Labels of the values the face fuzz adds to NaN, a string and None.
FACE_LABELS = ("+inf", "inf entry", "zero", "negative")


# ---- what is public --------------------------------------------------------------------------------------------
def _modules():
    """Every importable abrakit module (not ``cli``, not one whose name has a leading underscore)."""
    import abrakit

    for info in pkgutil.walk_packages(abrakit.__path__, "abrakit."):
        if any(part.startswith("_") for part in info.name.split(".")) or info.name.endswith(".cli"):
            continue
        try:
            yield importlib.import_module(info.name)
        except ImportError:            # an optional extra (numba, pypardiso) that is not installed
            continue


def _callable(obj) -> bool:
    return inspect.isfunction(obj) or (inspect.isclass(obj) and not issubclass(obj, BaseException))


def public_callables() -> dict[str, object]:
    """``{"module.name": callable}`` of the surface the fuzz guards: every function and class a module defines
    under a name without a leading underscore, keyed by its defining module. This holds every object the chapter
    faces list (they re-export the same objects, fuzzed once) and the public names of the implementation modules
    behind them; kernels carry a leading underscore and are left out."""
    return unprefixed_callables()


def unprefixed_callables() -> dict[str, object]:
    """The surface before it was curated: every function and class defined in a module whose name has no leading
    underscore (what the fuzz covered until each module declared its ``__all__``)."""
    found = {}
    for module in _modules():
        for name, obj in vars(module).items():
            if not name.startswith("_") and getattr(obj, "__module__", None) == module.__name__ and _callable(obj):
                found[f"{module.__name__}.{name}"] = obj
    return found



def face_callables() -> dict[str, tuple[str, str]]:
    """``{"module.name": (chapter, name on the face)}`` of every function and class a chapter face lists
    (``abrakit.<chapter>.__all__`` for the chapters of ``abrakit.MODULES``), keyed by its defining module."""
    import abrakit

    listed = {}
    for chapter in abrakit.MODULES:
        face = getattr(abrakit, chapter)
        for name in face.__all__:
            obj = getattr(face, name)
            if _callable(obj) and (getattr(obj, "__module__", "") or "").startswith("abrakit"):
                listed.setdefault(f"{obj.__module__}.{obj.__name__}", (chapter, name))
    return listed


def must_be_positive(name: str, parameter: str) -> bool:
    """Whether ``parameter`` of callable ``name`` must be positive (:data:`POSITIVE_NAME`, :data:`POSITIVE`,
    :data:`NOT_POSITIVE`)."""
    if (name, parameter) in NOT_POSITIVE:
        return False
    return (name, parameter) in POSITIVE or bool(POSITIVE_NAME.match(parameter))

def _code_of(obj):
    """The code object that runs when ``obj`` is called (a decorated function's own, not its wrapper's)."""
    target = obj.__init__ if inspect.isclass(obj) else inspect.unwrap(obj)
    return getattr(target, "__code__", None)


# ---- plain data --------------------------------------------------------------------------------------------------
def is_plain(value, depth: int = 0) -> bool:
    """Data that can be stored and replayed: numbers, strings, None, small arrays, containers and abrakit
    dataclasses of these."""
    if depth > 4:
        return False
    if value is None or isinstance(value, bool | int | float | str | complex | np.generic):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype != object and value.size <= MAX_ARRAY
    if isinstance(value, tuple | list):
        return len(value) <= 200 and all(is_plain(v, depth + 1) for v in value)
    if isinstance(value, dict):
        return len(value) <= 200 and all(isinstance(k, str) and is_plain(v, depth + 1) for k, v in value.items())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return type(value).__module__.startswith("abrakit") and all(
            is_plain(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value))
    return False


# ---- stage 1: harvest --------------------------------------------------------------------------------------------
class Harvester:
    """A profiler hook that keeps plain-data calls of the public callables."""

    def __init__(self, per_callable: int = PER_CALLABLE):
        self.targets = {}
        for name, obj in public_callables().items():
            code = _code_of(obj)
            if code is not None:
                self.targets[code] = (name, obj)
        self.per_callable = per_callable
        self.calls: dict[str, list[dict]] = defaultdict(list)
        self._seen: set = set()

    def hook(self, frame, event, arg):
        if event != "call":
            return
        target = self.targets.get(frame.f_code)
        if target is None:
            return
        name, obj = target
        if len(self.calls[name]) >= self.per_callable:
            return
        try:
            signature = inspect.signature(obj)
        except (TypeError, ValueError):
            return
        local = frame.f_locals
        kwargs = {}
        for p in signature.parameters.values():
            if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) or p.name not in local:
                return
            kwargs[p.name] = local[p.name]
        if not all(is_plain(v) for v in kwargs.values()):
            return
        try:
            key = (name, pickle.dumps(kwargs))
            if key in self._seen:
                return
            self._seen.add(key)
            self.calls[name].append(copy.deepcopy(kwargs))
        except Exception:      # noqa: BLE001 - anything that does not pickle is not kept
            return


HARVEST_OPTIONS = ("-q", "-m", "not slow", "-p", "no:cacheprovider", "--ignore=tests/test_api_fuzz.py")
"""pytest's options of a harvest: the fast tests, without the fuzz test itself (its replays with invalid input
would enter the catalogue as valid calls)."""


def harvest(tests=("tests",), out: Path = CATALOGUE, merge: bool = False) -> dict:
    """Run the tests (paths or pytest node ids) under the hook and pickle the calls found (``{name: [kwargs,
    ...]}``). ``merge``: add the calls found to the stored catalogue (:func:`merged`) instead of replacing it (a
    whole harvest takes about three hours under the profiler, one of a few test files minutes)."""
    import pytest

    harvester = Harvester()
    sys.setprofile(harvester.hook)
    try:
        pytest.main([*HARVEST_OPTIONS, *tests])
    finally:
        sys.setprofile(None)
    calls = {k: [c for c in v if len(pickle.dumps(c)) <= MAX_BYTES] for k, v in harvester.calls.items()}
    calls = {k: v for k, v in calls.items() if v}
    calls = {k: [pickle.dumps(c, protocol=pickle.HIGHEST_PROTOCOL) for c in v] for k, v in calls.items()}
    if merge and out.exists():
        calls = merged(pickle.loads(out.read_bytes())["calls"], calls)
    out.write_bytes(pickle.dumps({"format": 2, "calls": calls}, protocol=pickle.HIGHEST_PROTOCOL))
    return calls


def merged(stored: dict, harvested: dict) -> dict:
    """The stored catalogue with the harvested calls added: per callable, its stored calls and the harvested ones
    it did not have (a test that calls a function with invalid input, to check its refusal, must not replace the
    valid calls of another test)."""
    out = {name: list(calls) for name, calls in stored.items()}
    for name, calls in harvested.items():
        known = set(out.get(name, []))
        out.setdefault(name, []).extend(c for c in calls if c not in known)
    return out


def load_catalogue(path: Path = CATALOGUE) -> dict:
    """The harvested calls, with callables resolved by name; names that no longer exist are dropped."""
    stored = pickle.loads(Path(path).read_bytes())["calls"]
    calls = {}
    for name, kept in stored.items():        # one pickle per call: a call whose classes moved away is dropped
        for data in kept:
            try:
                kwargs = pickle.loads(data)
            except (ImportError, AttributeError):
                continue
            calls.setdefault(name, []).append(kwargs)
    for name, kwargs_list in _hand_calls().items():
        HAND_NAMES.add(name)
        calls.setdefault(name, []).extend(kwargs_list)
    public = public_callables()
    return {name: (public[name], kwargs_list) for name, kwargs_list in calls.items() if name in public}


# ---- stage 2: fuzz -----------------------------------------------------------------------------------------------
def finite(value, depth: int = 0) -> bool:
    """No NaN or infinity anywhere in ``value`` (arrays, numbers, containers, dataclass fields)."""
    if depth > 4:
        return True
    if isinstance(value, bool | str | type(None)):
        return True
    if isinstance(value, int | float | np.number):
        return bool(np.isfinite(value))
    if isinstance(value, np.ndarray):
        return value.dtype.kind not in "fc" or bool(np.all(np.isfinite(value)))
    if isinstance(value, tuple | list):
        return all(finite(v, depth + 1) for v in value[:1000])
    if isinstance(value, dict):
        return all(finite(v, depth + 1) for v in list(value.values())[:1000])
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return all(finite(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value))
    return True


def invalid_values(value, none_valid: bool):
    """``(label, bad value)`` for one argument: only values that are invalid for every numeric parameter (``None``
    unless ``none_valid``: a default of ``None`` or an annotation that allows it)."""
    out = []
    if isinstance(value, bool) or not isinstance(value, int | float | np.number | np.ndarray):
        return out
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "f" and value.size:
            bad = value.copy()
            bad.flat[0] = np.nan
            out.append(("nan entry", bad))
        return out
    out.append(("nan", float("nan")))
    out.append(("string", "abc"))
    if not none_valid:
        out.append(("none", None))
    return out


def face_invalid_values(value, positive: bool):
    """The values :func:`invalid_values` adds for a face callable: ``+inf`` for a number (an infinite first entry
    for a float array), and, where the parameter must be ``positive``, zero and a negative value (the first entry
    of an array)."""
    out = []
    if isinstance(value, bool) or not isinstance(value, int | float | np.number | np.ndarray):
        return out
    if isinstance(value, np.ndarray):
        if value.dtype.kind != "f" or not value.size:
            return out
        bad = value.copy()
        bad.flat[0] = np.inf
        out.append(("inf entry", bad))
        if positive:
            for label, entry in (("zero", 0.0), ("negative", -abs(float(value.flat[0])) or -1.0)):
                bad = value.copy()
                bad.flat[0] = entry
                out.append((label, bad))
        return out
    out.append(("+inf", float("inf")))
    if positive:
        kind = int if isinstance(value, int | np.integer) else float
        out.append(("zero", kind(0)))
        out.append(("negative", kind(-abs(value)) if value else kind(-1)))
    return out


class CallTimeout(Exception):
    """A fuzzed call ran longer than its time limit."""


def _alarm(signum, frame):
    raise CallTimeout


def outcome(call, kwargs, parameter, limit: float = 2.0) -> tuple[str, str]:
    """The class of one invalid call (:data:`OUTCOMES`, or ``"timeout"`` after ``limit`` seconds) and a short
    description."""
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, limit)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with np.errstate(all="ignore"):
                result = call(**kwargs)
    except CallTimeout:
        return "timeout", f"ran longer than {limit:g} s"
    except (ValueError, TypeError) as exc:
        text = str(exc)
        names = {parameter} | ({str(kwargs["name"])} if VALIDATORS.match(getattr(call, "__module__", "") or "")
                                and "name" in kwargs else set())         # a check names what it was told to
        return ("named" if any(n in text for n in names) else "unnamed"), f"{type(exc).__name__}: {text[:160]}"
    except Exception as exc:       # noqa: BLE001 - classifying every escape is the point
        return "deep", f"{type(exc).__name__}: {str(exc)[:160]}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    return ("accepted" if finite(result) else "non_finite"), ""


def replay(catalogue: dict, *, slow: float = SLOW_CALL, skip=()):
    """Run every call of the catalogue once; yield ``(name, call, kwargs, status, result)`` with ``status`` "ok",
    "slow" (ran longer than ``slow`` seconds) or "stale" (no longer runs: also a call the tests made inside
    ``pytest.raises``, which is harvested too; ``result`` then names the exception). Records and the callables in
    ``skip`` are left out."""
    for name, (call, kwargs_list) in sorted(catalogue.items()):
        if name in skip or name in RECORDS:
            continue
        declared = inspect.signature(call).parameters.values()
        fixed = [p for p in declared if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
        parameters = {p.name for p in fixed}
        required = {p.name for p in fixed if p.default is p.empty}
        open_ended = any(p.kind == p.VAR_KEYWORD for p in declared)       # **options: passed on by name
        for kwargs in kwargs_list:         # a harvested call names every parameter, a hand-written one the needed
            if not required <= set(kwargs) <= (set(kwargs) if open_ended else parameters):
                yield name, call, kwargs, "stale", "signature changed"
                continue
            start = time.perf_counter()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    result = call(**copy.deepcopy(kwargs))
            except Exception as exc:   # noqa: BLE001 - a call that no longer works is stale, not a finding
                yield name, call, kwargs, "stale", type(exc).__name__
                continue
            yield name, call, kwargs, ("slow" if time.perf_counter() - start > slow else "ok"), result


def fuzz(catalogue: dict, *, slow: float = SLOW_CALL, limit: float = 2.0, skip=()) -> dict:
    """Replay and mutate the catalogue; counts per outcome, non-finite results of valid calls, and the cases.

    Valid calls slower than ``slow`` seconds are not mutated (listed as ``slow``), a mutated call is stopped after
    ``limit`` seconds (``timeout``), and the callables named in ``skip`` are left out."""
    counts = Counter()
    face_counts = Counter()
    cases = []
    valid_non_finite, stale, skipped_slow = [], [], []
    functions = set()
    faces = face_callables()
    for name, call, kwargs, status, result in replay(catalogue, slow=slow, skip=skip):
        if status == "stale":
            stale.append(f"{name}: {result}")
            continue
        if status == "slow":
            skipped_slow.append(name)
            continue
        functions.add(name)
        counts["valid calls"] += 1
        if not finite(result) and name not in NON_FINITE_BY_DESIGN:
            valid_non_finite.append(name)
        signature = inspect.signature(call)
        for parameter, value in kwargs.items():
            if (name, parameter) in NAN_ALLOWED:
                continue
            declared = signature.parameters.get(parameter)      # None: passed on through **options
            none_valid = declared is None or declared.default is None or "None" in str(declared.annotation)
            bad_values = invalid_values(value, none_valid)
            if name in faces:
                bad_values += face_invalid_values(value, must_be_positive(name, parameter))
            bad_values = [(label, bad) for label, bad in bad_values if (name, parameter, label) not in ALLOWED]
            for label, bad in bad_values:
                mutated = copy.deepcopy(kwargs)
                mutated[parameter] = bad
                kind, text = outcome(call, mutated, parameter, limit)
                counts[kind] += 1
                if kind == "non_finite" and label in FINITE_LABELS:
                    counts["non_finite_from_finite"] += 1
                if name in faces:
                    face_counts[kind] += 1
                    if kind == "non_finite" and label in FINITE_LABELS:
                        face_counts["non_finite_from_finite"] += 1
                cases.append({"callable": name, "parameter": parameter, "value": label, "outcome": kind,
                              "message": text})
    counts["invalid calls"] = sum(counts[k] for k in OUTCOMES)
    face_counts["invalid calls"] = sum(face_counts[k] for k in OUTCOMES)
    keys = ("valid calls", "invalid calls", *OUTCOMES, "non_finite_from_finite")
    return {"functions": len(functions), "counts": {k: counts[k] for k in keys},
            "face_counts": {k: face_counts[k] for k in keys[1:]},
            "valid_non_finite": sorted(set(valid_non_finite)), "stale": sorted(set(stale)),
            "slow": sorted(set(skipped_slow)), "fuzzed": sorted(functions),
            "skipped": sorted(set(skip) & set(catalogue)),
            "cases": [c for c in cases if c["outcome"] != "named"]}


def face_report(catalogue: dict, result: dict | None = None) -> dict[str, str]:
    """``{"module.name": how}`` for every callable a chapter face lists: ``"harvested"`` or ``"hand"``
    (:data:`HAND_CALLS`) where the catalogue holds a valid call of it, ``"record"`` for the records of
    :data:`RECORDS` (their fields are outputs), ``"none"`` where it has no valid call. With the ``result`` of
    :func:`fuzz`, a call that did not run ``"slow"`` or ``"stale"`` is marked so (``"harvested, slow"``)."""
    fuzzed = set(result["fuzzed"]) if result else None
    slow = set(result["slow"]) if result else set()
    out = {}
    for name in sorted(face_callables()):
        if name in RECORDS:
            out[name] = "record"
        elif name not in catalogue:
            out[name] = "none"
        else:
            how = "hand" if name in HAND_NAMES else "harvested"
            if fuzzed is not None and name not in fuzzed:
                how += ", slow" if name in slow else (", skipped" if name in result["skipped"] else ", stale")
            out[name] = how
    return out


def valid_calls(catalogue: dict, *, slow: float = SLOW_CALL, skip=()) -> list[tuple[str, object, dict]]:
    """``(name, callable, kwargs)`` of the catalogue's calls that still run within ``slow`` seconds."""
    return [(name, call, kwargs) for name, call, kwargs, status, _ in replay(catalogue, slow=slow, skip=skip)
            if status == "ok"]


def names_a_parameter(call, text: str) -> bool:
    """Whether an error message names one of ``call``'s parameters."""
    try:
        return any(p in text for p in inspect.signature(call).parameters)
    except (TypeError, ValueError):
        return False


def report(result: dict) -> str:
    counts = result["counts"]
    lines = [f"{result['functions']} callables, {counts['valid calls']} valid calls, "
             f"{counts['invalid calls']} invalid calls"]
    lines += [f"  {k:11s} {counts[k]}" for k in OUTCOMES]
    lines.append(f"  non_finite_from_finite {counts['non_finite_from_finite']}")
    lines.append(f"  face callables: {result.get('face_counts')}")
    if "faces" in result:
        how = Counter(v for v in result["faces"].values())
        lines.append(f"  face coverage: {dict(how)} of {len(result['faces'])}")
    lines.append(f"  valid calls with NaN/inf results: {len(result['valid_non_finite'])} "
                 f"{result['valid_non_finite'][:8]}")
    by = defaultdict(Counter)
    for case in result["cases"]:
        if case["outcome"] != "named":
            by[case["callable"]][case["outcome"]] += 1
    lines += [f"  {name}: {dict(c)}" for name, c in sorted(by.items())]
    return "\n".join(lines)


if __name__ == "__main__":
    import argparse
    import json

    parser = argparse.ArgumentParser(description="Fuzz abrakit's public API with invalid input")
    parser.add_argument("stage", choices=("harvest", "fuzz"))
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "results" / "api_fuzz.json")
    parser.add_argument("--merge", action="store_true", help="harvest: add the calls found to the stored "
                                                              "catalogue")
    parser.add_argument("tests", nargs="*", default=["tests"], help="harvest: test files or node ids (all tests)")
    args = parser.parse_intermixed_args()
    if args.stage == "harvest":
        found = harvest(args.tests, merge=args.merge)
        print(f"harvested {sum(map(len, found.values()))} calls of {len(found)} callables into {CATALOGUE}")
    else:
        catalogue = load_catalogue()
        result = fuzz(catalogue)
        result["faces"] = face_report(catalogue, result)
        result["surface"] = {"public (__all__)": len(public_callables()),
                             "without a leading underscore": len(unprefixed_callables())}
        args.out.write_text(json.dumps({k: v for k, v in result.items()}, indent=1, allow_nan=False))
        print(report(result))
