"""Regularised damage-plasticity (Ch. 6-7): Model I (gradient-enhanced, element Laplacian) and Model II (ERVE);
and the anisotropic softening damage of seed 001, regularised by its crack band (:mod:`.crack_band`)."""

from abrakit.damage.crack_band import CrackBandBar
from abrakit.damage.laplacian import (
    ElementLaplacian,
    element_centres,
    element_laplacian,
    face_neighbours,
    ghost_centres,
    mirror_points,
    taylor_matrix,
    unit_cube_mesh,
)
from abrakit.damage.localisation import localisation_study, run_bar
from abrakit.damage.model_one_fe import ModelIResult, ModelISolver, solve_model_one
from abrakit.damage.model_one_path import DamageControl, ModelIPathFollowingSolver, ModelIPathResult
from abrakit.damage.model_two_fe import ModelTwoResult, run_model_two
from abrakit.damage.runs import SpecimenRun, run_specimen
from abrakit.damage.specimens import Specimen, specimen

__all__ = [
    "CrackBandBar",
    "ElementLaplacian",
    "element_centres",
    "element_laplacian",
    "face_neighbours",
    "ghost_centres",
    "mirror_points",
    "taylor_matrix",
    "unit_cube_mesh",
    "localisation_study",
    "run_bar",
    "ModelIResult",
    "ModelISolver",
    "solve_model_one",
    "DamageControl",
    "ModelIPathFollowingSolver",
    "ModelIPathResult",
    "ModelTwoResult",
    "run_model_two",
    "Specimen",
    "run_specimen",
    "SpecimenRun",
    "specimen",
]
