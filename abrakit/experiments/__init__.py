"""DEM experiments of Ch. 5.3–5.4 and 8.3: specimen genesis, compression tests, checks of the closed forms.

=====================================  ==================================================================
:mod:`.specimen`                       genesis (Ch. 5.3.1): expansion, consolidation, bonds, cached specimens
:mod:`.compression`                    strain-controlled tests, the three measurement schemes (Fig. 5.2)
:mod:`.closed_form_checks`             Eq. (5.20)/(5.26) against the DEM, envelopes, grain shape (Ch. 5.4)
:mod:`.bending`                        four-point bending fatigue of a cemented beam (seed 002, Sec. 5)
=====================================  ==================================================================
"""

from abrakit.experiments import contacting
from abrakit.experiments.closed_form_checks import (
    bond_strength_case,
    contact_statistics,
    elastic_case,
    envelope_case,
    mean_interval,
    mohr_coulomb_fit,
)
from abrakit.experiments.compression import (
    compression_test,
    elastic_test,
    strength_test,
)
from abrakit.experiments.specimen import Material, Specimen, SpecimenSpec, genesis
from abrakit.experiments.sweeps import case_key, load_sweep, run_sweep

__all__ = ["Material", "Specimen", "SpecimenSpec", "bond_strength_case", "case_key", "compression_test",
           "contact_statistics", "contacting", "elastic_case", "elastic_test", "envelope_case", "genesis",
           "load_sweep", "mean_interval", "mohr_coulomb_fit", "run_sweep", "strength_test"]
