"""Regularised damage-plasticity (Ch. 6-7): Model I (gradient-enhanced, element Laplacian) and Model II (ERVE);
and the anisotropic softening damage of seed 001, regularised by its crack band (:mod:`.crack_band`)."""

from abrakit.damage.crack_band import CrackBandBar, DoubleCantileverBeam
from abrakit.damage.laplacian import element_laplacian, face_neighbours
from abrakit.damage.localisation import E_BAR, bar_mesh, bar_models, cross_section, localisation_study, run_bar
from abrakit.damage.metrics import band_width, mesh_study, path_work, specimen_metrics, work
from abrakit.damage.model_one_fe import ModelISolver
from abrakit.damage.model_one_path import DamageControl, ModelIPathFollowingSolver
from abrakit.damage.model_two_fe import ModelTwoResult, default_material, rate_limit_work, run_model_two
from abrakit.damage.runs import REGULARISATION, SpecimenRun, run_specimen
from abrakit.damage.specimens import SPECIMENS, DamageSpecimen, plot_field, specimen

__all__ = [
    # the localising bar (Ch. 6.4)
    "E_BAR", "bar_mesh", "bar_models", "cross_section", "run_bar", "localisation_study",
    # Model I: the element Laplacian and its solvers (Ch. 7.1)
    "element_laplacian", "face_neighbours", "ModelISolver", "ModelIPathFollowingSolver", "DamageControl",
    # Model II (Ch. 7.2)
    "default_material", "run_model_two", "ModelTwoResult", "rate_limit_work",
    # the three specimens and the comparison of the models (Ch. 7.3)
    "specimen", "SPECIMENS", "DamageSpecimen", "plot_field", "run_specimen", "SpecimenRun", "REGULARISATION",
    "specimen_metrics", "mesh_study", "work", "path_work", "band_width",
    # the crack band of seed 001
    "CrackBandBar", "DoubleCantileverBeam",
]
