"""DEM experiments of Ch. 5.3–5.4 and 8.3: specimen genesis, compression tests, checks of the closed forms.

=====================================  ==================================================================
:mod:`.specimen`                       genesis (Ch. 5.3.1): expansion, consolidation, bonds, cached specimens
:mod:`.compression`                    strain-controlled tests, the three measurement schemes (Fig. 5.2)
:mod:`.closed_form_checks`             Eq. (5.20)/(5.26) against the DEM, envelopes, grain shape (Ch. 5.4)
:mod:`.periodic_cell`                  a periodic cell of the same grains, probed by six strains (Ch. 5.4)
:mod:`.sweeps`                         parameter studies written case by case, read back as records
:mod:`.contacting`                     a grain bed pressed onto a plate: which grains touch it (Ch. 8.3)
:mod:`.disk_packing`                   graded disk packings of a Fuller curve
:mod:`.bending`                        the four-point beam of a cemented DEM (seed 002, Sec. 5), monotonic test
:mod:`.cyclic`                         its cyclic test: cycle jump, fatigue life, stages (seed 002, Sec. 5.2)
=====================================  ==================================================================
"""

from abrakit.experiments.bending import (
    BeamSpec,
    beam_theory_deflection,
    flexural,
    four_point_beam,
    monotonic_bending,
    table_two,
    uniaxial_modulus,
)
from abrakit.experiments.closed_form_checks import (
    BOND_CASES,
    DEMO_SPEC,
    bond_strength_case,
    contact_statistics,
    elastic_predictions,
)
from abrakit.experiments.compression import SCHEMES, elastic_test, force_carrying_contacts
from abrakit.experiments.contacting import SEED_COEFFICIENT, contact_census, count_touching, pressed_bed, touching_mask
from abrakit.experiments.cyclic import cyclic_bending, stage_slopes
from abrakit.experiments.disk_packing import fuller_passing
from abrakit.experiments.periodic_cell import periodic_genesis
from abrakit.experiments.specimen import DemMaterial, DemSpecimen, SpecimenSpec, genesis
from abrakit.experiments.sweeps import load_sweep, run_sweep

__all__ = [
    # specimen genesis and the compression tests (Ch. 5.3)
    "SpecimenSpec", "genesis", "DemSpecimen", "DemMaterial", "elastic_test", "SCHEMES", "force_carrying_contacts",
    "periodic_genesis",
    # the closed forms against the DEM (Ch. 5.4)
    "DEMO_SPEC", "BOND_CASES", "contact_statistics", "elastic_predictions", "bond_strength_case",
    # grains that touch a plate (Ch. 8.3)
    "pressed_bed", "contact_census", "touching_mask", "count_touching", "SEED_COEFFICIENT",
    # four-point bending of a cemented beam (seed 002)
    "BeamSpec", "four_point_beam", "monotonic_bending", "cyclic_bending", "flexural", "beam_theory_deflection",
    "uniaxial_modulus", "stage_slopes", "table_two", "fuller_passing",
    # studies
    "run_sweep", "load_sweep",
]
