"""Every decision the toolkit takes where the seed is ambiguous, misprinted or silent, with its reason and its test.

The book's page "Decisions" renders :data:`DECISIONS`; ``tests/test_decisions.py`` checks that every test named
here exists, so a decision cannot lose the test that pins it without the suite noticing. Each entry also stands in
the chapter that uses it and in the docstring of the code that implements it.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["DECISIONS", "Decision", "markdown"]


@dataclass(frozen=True)
class Decision:
    """``topic``: what is decided; ``seed``: what the seed prints or leaves open; ``ours``: what the toolkit does;
    ``reason``: why; ``tests``: ``"tests/<file>.py::<test>"`` or ``"benchmarks/<file>.py"`` entries that pin it;
    ``chapter``: the book chapter (file name without ``.md``) where it is explained."""

    topic: str
    seed: str
    ours: str
    reason: str
    tests: tuple[str, ...]
    chapter: str
    kind: str = "misprint"   # "misprint", "ambiguity", "reconstruction" or "choice"


BOND = "tests/test_fatigue_bond.py::"
BEND = "tests/test_experiments_bending.py::"
AD = "tests/test_anisotropic_damage.py::"
CB = "tests/test_crack_band.py::"
ERO = "tests/test_scratch_erosion.py::"

DECISIONS: tuple[Decision, ...] = (
    Decision("switch of the rate law, Eq. (2.112)", "|p| > r₂", "|p| > r₁",
             "r₂ is a viscosity (MPa s), r₁ the threshold (MPa); the printed switch compares unlike units and lets "
             "λ fall for r₂ < |p| < r₁", ("tests/test_evolution.py::test_eq_2112_switches_on_r1_not_r2",), "evolution"),
    Decision("explicit update, Eq. (4.53)", "λᵐ + Δt/r₂ p − r₁", "λᵐ + Δt/r₂ [|p| − r₁]₊",
             "as printed λ moves without driving force (p = 0)",
             ("tests/test_evolution.py::test_eq_453_as_printed_moves_lambda_without_driving_force",), "evolution"),
    Decision("yield function, Table 6.1", "‖dev σ‖ − (r_p − K_H α_p)", "‖dev σ‖ − (r_p + K_H α_p)",
             "K_H > 0 must harden, as Eqs. (6.53) and (6.61) do",
             ("tests/test_materials_plasticity.py::test_uniaxial_yield_stress_and_hardening_modulus_of_the_yield_"
              "function",), "plasticity"),
    Decision("stress of the operator split, Eq. (6.62)", "σᵐ + fᵐ E:(εᵐ⁺¹ − ε_pᵐ)", "fᵐ E:(εᵐ⁺¹ − ε_pᵐ⁺¹), as (6.40)",
             "the printed form adds the old stress to a total-strain expression",
             ("tests/test_materials_damage.py::test_model_one_returns_exactly_the_operator_split_tangent_f_m_E",),
             "plasticity"),
    Decision("range of Model I's damage variable", "d ∈ [0, 1)", "d ∈ [0, 13.8], f = e⁻ᵈ ≥ 10⁻⁶",
             "f = e⁻ᵈ allows any d ≥ 0; capping d below 1 would keep 37 % of the stiffness in a crack",
             ("tests/test_damage_model_one.py::test_uniform_bar_follows_the_closed_form_and_keeps_f_in_range",
              "tests/test_materials_base.py::test_invalid_parameters_raise_value_error_naming_them"), "plasticity",
             "ambiguity"),
    Decision("damage derivative of the ERVE stiffness, Eqs. (6.102), (6.105)", "f̄ f′/(n f²)", "f̄² f′/(n f²), as (6.94)",
             "the derivative of f̄ = n / Σ 1/f_i; the printed one misses a factor f̄",
             ("tests/test_materials_damage.py::test_model_two_seed_tangent_6_105",
              "tests/test_materials_damage.py::test_erve_identities_6_87_to_6_94"), "plasticity"),
    Decision("Model I's damage update, Algorithm 1", "one Newton step per element, Λ_f from fᵐ",
             "the coupled complementarity problem of all elements (the seed's scheme on request)",
             "the seed's update lags by β/(Ψ̄₀h²) per step, which reads as mesh dependence",
             ("tests/test_damage_model_one.py::test_seed_scheme_lags_and_converges_to_the_coupled_one_with_the_step",
              "tests/test_damage_model_one.py::test_coupled_equals_the_seed_update_for_a_single_active_element"),
             "model_one", "choice"),
    Decision("Model II's rate limit under path following", "external power ℓ_ext at a prescribed load",
             "|work of the reactions| of the step; the book computes Model II under displacement control",
             "the load factor is an unknown, so the power may change sign through a snap-back; Model II itself "
             "has none (no damage grows at a constant displacement: the force drop of a step halves with the "
             "step), and arc length creeps at the plate's peak because the rate limit moves with the load factor",
             ("tests/test_damage_model_two.py::test_arc_length_follows_model_two_to_fracture_"
              "like_displacement_control",
              "tests/test_damage_model_two.py::test_model_two_does_not_snap_back_its_largest_drop_halves_with_the_step",
              "tests/test_damage_model_two.py::test_arc_length_creeps_at_the_plate_peak_because_the_rate_limit_"
              "follows_the_load_factor", "benchmarks/bench_model_two_steps.py"), "model_two", "ambiguity"),
    Decision("stiffness identification, Eqs. (5.20), (5.21)", "published form (α = 1)",
             "both: ``published`` and the variationally consistent form (÷ α²)",
             "the published form violates its own kinematic constraint for an affine field and can exceed the "
             "affine (Voigt) bound", ("tests/test_identification.py::test_affine_field_violates_the_published_"
                                     "constraint_and_meets_the_consistent_one",
                                     "tests/test_identification.py::test_published_modulus_exceeds_the_affine_upper_"
                                     "bound_above_a_critical_ratio"), "identification", "ambiguity"),
    Decision("strain of a periodic cell, the elastic probe", "silent (the seed's tests are walled)",
             "a jump of the cell and the positions that also shifts every touching contact's tangential spring by "
             "−K^t (ε l)_t; six Voigt strains; E, ν from the isotropic projection of the 6 × 6 stiffness",
             "the tangential spring is incremental (Eq. 4.7): a positions-only jump never reaches it and the probe "
             "measures a network without shear springs (ν ≈ 1/4, E 27–41 % low); for an infinitesimal strain the "
             "shift equals what a velocity-driven cell accumulates and needs no image velocities in the contact laws",
             ("tests/test_dem_network.py::test_the_probe_equals_the_exact_network_response",
              "tests/test_dem_network.py::test_without_the_spring_shift_the_probe_misses_the_tangential_springs",
              "tests/test_dem_network.py::test_velocity_driven_motion_loads_the_springs_as_the_jump_does",
              "tests/test_dem_network.py::test_the_stress_right_after_the_jump_is_the_affine_closed_form",
              "benchmarks/bench_dem_periodic.py"), "dem_identification", "choice"),
    Decision("the wear rate against the ASTM G65 test", "rates in m³/s; 'measured losses are lower'",
             "the volume loss per procedure in mm³ beside the standard's 100 mm³ threshold and the measured range, "
             "the sand's volume flow, grain counts (seed, monolayer, sand feed, load), the contact by Hertz's line "
             "contact with Gent's rubber modulus, and the chain held to the test's 130 N (grooves ∝ F^{3/2})",
             "the chain credits 10⁴ grains with the groove of a 2 N scratch, 2 × 10⁴ N in all against 130 N; held "
             "to the test's force it brackets the measured losses (9.2 × 10³ and 7 × 10² mm³ for 100 µm sand)",
             ("tests/test_g65.py::test_table_8_4_against_the_real_test",
              "tests/test_g65.py::test_rubber_modulus_by_gent_and_the_hertz_contact_of_the_wheel",
              "tests/test_g65.py::test_the_plastic_groove_grows_as_the_load_to_the_power_three_halves"), "wear",
             "reconstruction"),
    Decision("the degree of wear of one grain", "read from one section of a 100 µm scratch (0.37 and 0.12)",
             "the steady rate of the volume budget, (rate of A_g − rate of A_s)/rate of A_g, over the second half "
             "of a 400 µm slide on a 500 µm block, on the coarse mesh, interpolated to 2 N between two depths "
             "as in Table 8.4; its uncertainty from 50 µm windows, nine wake sections and the same 400 µm slides "
             "on the demo mesh (at most 0.002 apart)",
             "the sections and rates fall along the wake: over 50 µm windows 0.29, 0.12, 0.05–0.06 on every grain, "
             "then level off at 0.03 after about 250 µm of slide (13 footprint radii) at d ≈ 2 µm, and keep "
             "falling slowly at d = 4 µm (0.024, 0.014, 0.010, 0.008: an upper estimate); the second half of a "
             "200 µm slide (0.056 on three mesh levels of the seed's scene, 0.08–0.09 for the grains) still lies "
             "in the transient", ("benchmarks/bench_scratch_steady.py",
                                  "tests/test_benchmarks.py::test_the_grains_steady_degree_of_wear_is_read_beyond_"
                                  "the_slide_transient",
                                  "tests/test_benchmarks.py::test_the_steady_degree_of_wear_changes_little_between_"
                                  "the_mesh_levels",
                                  "tests/test_scratch_budget.py::test_steady_rates_are_the_slopes_over_the_window_"
                                  "and_give_eq_8_5_in_rates"),
             "scratch_to_wear", "choice"),
    Decision("load increments of the scratch", "not stated (an Abaqus/Standard run)",
             "indentation in 5 increments, the slide in h_z/4 increments starting at a quarter of one, Newton's "
             "correction criterion 10⁻² of the increment (Abaqus' default), residual 10⁻⁴ of the largest force",
             "fewer Newton iterations for the same grooves (within 2 %); larger slide increments cut back",
             ("tests/test_scratch_scene.py::"
              "test_the_faster_increment_control_changes_no_groove_beyond_its_tolerances",
              "benchmarks/bench_scratch_speed.py"), "scratch", "choice"),
    Decision("contact area of Table 8.4", "not stated", "A_c = 114.62 mm², derived from the table",
             "one area reproduces every printed rate to its printed digits; the midpoint of the admissible band",
             ("tests/test_wear.py::test_scaling_area_is_derived_from_the_table",
              "tests/test_wear.py::test_table_8_4_every_row_within_one_percent_and_to_the_printed_digits"), "wear",
             "reconstruction"),
    Decision("units of α in Table 8.2", "1/s", "1/(N mm), as Table 7.2 and Eq. (6.98)",
             "the rate limit ḋ ≤ α ℓ_ext needs 1/(N mm) to be dimensionless in d",
             ("tests/test_scratch_scene.py::test_model_two_damage_obeys_the_rate_limit_of_the_tip_work",), "scratch"),
    Decision("double-notched strip, Fig. 7.8 (lost)", "dimensions in a missing figure",
             "50 × 100 mm, notches 10 × 2 mm at mid-height ± 10 mm",
             "Model I's band joins the notch tips from β ≈ 4 on this geometry, at β = 1 with notches ± 5 mm",
             ("benchmarks/bench_double_notch_length.py",
              "tests/test_damage_specimens.py::test_conditions_and_loaded_edge"), "comparison", "reconstruction"),
    Decision("grip of the Chapter 7 specimens", "a prescribed displacement of the top edge",
             "kept: uniform displacement, the edge does not rotate",
             "it is what the seed prescribes; it damages the sharp notch's top-right corner, which a traction "
             "does not", ("tests/test_damage_model_two.py::test_sharp_notch_corner_damage_comes_from_the_grip",
                          "benchmarks/bench_sharp_notch_edge.py"), "comparison", "choice"),
    Decision("Model I under path following", "Algorithm 1 under displacement control only",
             "Newton and damage update repeated within a path-following step until they agree",
             "the staggered update passes snap-backs as jumps that lose energy; the converged sweeps follow them",
             ("tests/test_damage_model_one_path.py::test_snap_back_is_followed_without_cutbacks_where_displacement_"
              "control_jumps",), "model_one", "choice"),
    Decision("depths of the 2 N grains", "not stated", "interpolated in F_N between bracketing F-bar runs",
             "a fully plastic contact carries F ∝ 2Rd; bracketing runs need no re-run when a guess misses",
             ("benchmarks/bench_scratch_steady.py",), "scratch_volume", "reconstruction"),
    Decision("kinematics of the scratch", "small strain (implied)", "finite strain, F-bar hexahedra, logarithmic J2",
             "strains under the tip reach order one; small strain changes f_ab by up to 0.07 between meshes",
             ("tests/test_finite_strain.py::test_fbar_tangent_is_the_derivative_of_its_force",), "scratch_volume",
             "choice"),
    Decision("damage and removal in the finite-strain scratch", "Model II on top of the plasticity (Table 8.2), "
             "small strain, removal not defined",
             "Model II on logarithmic strains (the ERVE's f̄ scales the Kirchhoff stress, the return stays radial); an "
             "element whose mean largest sub-domain damage reaches the cap 0.999 is removed: its current volume "
             "leaves the shoulders or the prow (above y = 0) or deepens groove and sink (below), a 'removed' term "
             "of the volume audit that keeps it exact",
             "the scene's physics is finite strain, and plowing conserves volume: wear must come from removed "
             "material; counting it inside the audit keeps the budget closed and Eq. (8.5) counts it as worn",
             ("tests/test_finite_strain_damage.py::test_small_strains_reduce_to_the_small_strain_model_with_damage",
              "tests/test_finite_strain_damage.py::test_the_energy_budget_closes_at_large_strain_to_first_order_in_"
              "the_step",
              "tests/test_finite_strain_damage.py::test_a_rigid_rotation_of_a_damaged_point_changes_no_stress_"
              "invariant",
              "tests/test_scratch_budget.py::test_removed_elements_close_the_budget_and_move_volume_from_the_"
              "shoulders_to_the_debris"), "scratch_volume", "choice"),
    Decision("ductile failure of the scratch's steel", "no removal criterion (Ch. 8 describes none; Sec. 8.2.1 "
             "credits the ERVE damage with the volume loss); no fracture data for St-52",
             "D = Σ Δε̄ᵖ/ε_f(η) with Johnson & Cook's ε_f = D₁ + D₂ exp(D₃η) (Eng. Fract. Mech. 21 (1985) 31; "
             "rate and temperature factors 1: quasi-static, room temperature) and their 4340 steel's D₁, D₂, D₃ = "
             "0.05, 3.44, −2.12; no damage for η ≤ −1/3 (Bao & Wierzbicki, Eng. Fract. Mech. 72 (2005) 1049); "
             "ε̄ᵖ = √(2/3) α_p and η of the Kirchhoff stress at the end of a converged increment, a post-processing "
             "that leaves the plasticity's results unchanged",
             "of Johnson and Cook's three metals only 4340 is a steel, and its D₁ > 0 keeps ε_f positive at every "
             "triaxiality (Armco iron's fit, ferritic and nearer St-52's 355 MPa in yield, reaches zero at "
             "η ≈ 1.9); its ε_f = 1.75 in tension (3.49 in shear) exceeds a structural steel's true fracture strain "
             "of order 1, so the choice errs towards less removal; Armco iron and OFHC copper are kept for "
             "sensitivity",
             ("tests/test_ductile_failure.py::test_johnson_cook_fracture_strain_of_4340_steel_and_the_cut_off",
              "tests/test_ductile_failure.py::test_finite_strain_hook_reaches_failure_at_the_fracture_strain",
              "tests/test_ductile_failure.py::test_with_the_cut_off_no_damage_grows_at_triaxiality_minus_0_4_for_"
              "any_strain"), "material_removal", "choice"),
    Decision("removal in the scratch", "none described (Ch. 8); the ERVE damage is credited with the volume loss",
             "staggered element erosion: after a converged increment, an intact element whose nonlocal ductile "
             "damage D̄ (bell-shaped average over the intact elements within ℓ = 1 µm) reaches 1 leaves the "
             "stiffness (a residual spring 10⁻⁶ E), the contact (its surface nodes, once all their elements are "
             "eroded) and enters the volume budget's removed term; the next increment re-equilibrates",
             "an implicit scene cannot delete elements inside Newton; the nonlocal length stops the removal from "
             "following one element row; ℓ = 1 µm is half the seed's depth, so a 2 µm groove can shed a layer, and "
             "is resolved by the meshes the map uses",
             (ERO + "test_the_step_erodes_the_elements_that_failed_and_releases_their_stored_energy",
              ERO + "test_eroded_elements_are_left_out_of_the_nonlocal_average",
              ERO + "test_a_cutting_scratch_erodes_elements_and_keeps_its_budget_closed",
              "benchmarks/bench_scratch_removal.py"), "material_removal", "choice"),
    Decision("the f_ab that feeds Eq. (8.13)", "Eq. (8.5) on one mid-length cross-section read with the tip in "
             "contact (Sec. 8.4)",
             "the removal fraction: the rate of removed volume over the rate of groove volume along the steady "
             "slide (SteadyRates.removal_fraction); the seed's reading is kept under its own name (seed_f_ab)",
             "Eq. (8.5) counts every groove volume that is not in the shoulders as worn, including the elastic "
             "compaction of the wake and the prow, which no wear test weighs",
             (ERO + "test_the_removal_fraction_is_the_removed_rate_over_the_groove_rate",), "material_removal",
             "ambiguity"),
    Decision("the force on a G65 grain", "2 N on every grain (the single scratch's), 1.03·10⁴ grains in contact",
             "the wheel's Hertz pressure over the contact zone, shared over the seed's N_c grains one per cell, "
             "summing to the procedure's force; each grain's plastic contact F = H π a²/2 with H the scratch "
             "scene's own mean contact pressure",
             "2 N on each of 10⁴ grains is 160 times the test's 130 N",
             ("tests/test_g65.py::test_the_grain_forces_share_the_wheels_force_by_its_hertz_pressure",
              "tests/test_g65.py::test_the_balanced_loss_is_the_grains_grooves_at_their_own_forces"),
             "material_removal", "choice"),
    Decision("stick/slip chatter of the scratch's contact nodes", "silent (Abaqus' penalty contact)",
             "a node that switches stick <-> slip (or reverses its slip) twice in one increment slips along its "
             "last slip direction for the rest of it (|t_T| = μp); the held nodes' share of the Coulomb force is "
             "reported",
             "nodes pushed along at the front of the prow sit at the cone's edge with a slip of 0.3 nm per step; "
             "Newton cycled at their friction force and the demo-mesh scene stopped at 97 % of its slide; holding "
             "them in stick left the cone by up to 84 % of the contact's Coulomb force",
             ("tests/test_scratch_scene.py::test_a_node_that_chatters_between_stick_and_slip_slips_along_a_held_"
              "direction_for_the_rest_of_the_step",), "scratch", "choice"),
    Decision("α of the bond's yield surface, seed 002 Eq. (18)", "garbled: '.2K 9 8 9 L M − 8 9 L M / K9'",
             "α = √(2cσ_t tan φ − σ_t² tan² φ)/c",
             "the only reading under which the surface passes through both strengths the prose names: σ_t(1 − D) at "
             "σ_s = 0 and c(1 − D) at σ_n = 0; the prose's 'shear has just reached yield at D = 0.4 under 60 kPa' "
             "then holds exactly",
             (BOND + "test_yield_surface_passes_through_the_tensile_strength_and_the_cohesion",
              BOND + "test_table_one_reading_agrees_with_the_prose"), "fatigue", "reconstruction"),
    Decision("damage of the bond, seed 002 Eqs. (17), (21), (22)", "ΔD = χ[1 − exp(−Δκ)], χ = exp(−κ), from D₀",
             "χ = 1 − D, so D = 1 − (1 − D₀) e^(−κ)",
             "the printed χ sums to D₀ + 1 − e^(−κ), which passes 1 for D₀ > 0; both agree at D₀ = 0",
             (BOND + "test_damage_law_composes_and_stays_below_one",
              BOND + "test_monotonic_tests_peak_at_the_strengths_and_dissipate_the_softening_area"), "fatigue",
             "reconstruction"),
    Decision("far branch of the bond's hyperbola", "F = α²σ_s² − q² + q₀² (q = c(1 − D) − σ_n tan φ)",
             "−q|q| for −q²", "the printed F turns negative again far on the tension side, where a large trial "
             "stress would read as elastic",
             (BOND + "test_yield_surface_passes_through_the_tensile_strength_and_the_cohesion",), "fatigue", "choice"),
    Decision("geometric factor, seed 002 Eq. (31)", "(1 − 0.025D² + 0.06D⁴) sec(πD/2) (root lost)",
             "(1 − 0.025D² + 0.06D⁴) √sec(πD/2), Tada et al. (1973)",
             "Tada's centre-cracked strip; it meets Isida's exact values to 0.1 %, the printed form misses them by "
             "19 % at D = 0.5 and 48 % at 0.7",
             (BOND + "test_geometric_factor_is_the_centre_cracked_strip",), "fatigue", "misprint"),
    Decision("fatigue threshold a of Table 1", "not listed; the prose asks a < 0.6",
             "a = 0.5", "the 60 kPa cycles must exceed the fatigue criterion in tension (a < 0.505) as well as in "
             "shear for the two histories to coincide, as the paper states",
             (BOND + "test_table_one_reading_agrees_with_the_prose",
              BOND + "test_tension_and_shear_fatigue_histories_coincide"), "fatigue", "reconstruction"),
    Decision("mode I stress range, seed 002 Eq. (29)", "Δσ_n = σ_n^max − σ_n^min",
             "⟨σ_n^max⟩ − ⟨σ_n^min⟩ (tensile parts)", "a crack closed in compression sees no mode I loading; equal "
             "to the printed range for the paper's tension cycles",
             (BOND + "test_mixed_mode_range_adds_in_quadrature",), "fatigue", "choice"),
    Decision("cycle counts of Fig. 11", "2008 (m = 0.8) and 50 (m = 1.2) cycles for 20–60 kPa cycles",
             "the printed range (40 kPa): 2777 and 80; the paper's counts are reproduced to the cycle by a 60 kPa "
             "range", "the equations give 2777 and 80; the paper's numbers correspond to ΔK from the 60 kPa peak, "
             "as if the cycle's minimum were taken as 0; its cycle-jump percentages say the same",
             (BOND + "test_papers_cycle_counts_are_those_of_a_zero_to_peak_stress_range",
              BOND + "test_papers_cycle_jump_counts_are_ratios_of_a_zero_to_peak_run"), "fatigue", "ambiguity"),
    Decision("cycle jump count, seed 002 Eq. (40)", "N_jump = ΔD_jump / ΔD_max (not an integer)",
             "rounded to the nearest integer, at least 1",
             "rounding, with no jump passing the cycle that reaches the target damage, reproduces the paper's "
             "797.4 % (311/39) and 388.8 % (311/80) to the digit; "
             "'reduce by' is read as the ratio full/simulated",
             (BOND + "test_papers_cycle_jump_counts_are_ratios_of_a_zero_to_peak_run",), "fatigue", "reconstruction"),
    Decision("particles of the bending beam, seed 002 Sec. 5.1", "poly-disperse, radii 1–19 mm after the "
             "aggregate grading (Fig. 13, lost)", "two samples: a hexagonal lattice, radii in [0.8 r̄, r̄] (the "
             "default), and a packing after Fuller's grading (area passing ∝ √r) between r̄/3 and r̄ = 4–6 mm, "
             "settled at 1 kPa and bonded where the gap is below a tenth of the smallest radius",
             "the paper's curve is lost; Fuller's is the classical aggregate grading. Radii down to 1 mm would make "
             "the monotonic test hours long, so the grading is truncated; the lattice needs no genesis, one number "
             "sets its resolution, and its elastic beam can be checked against the same material in uniaxial "
             "tension", (BEND + "test_elastic_beam_modulus_is_timoshenkos_with_the_uniaxial_"
                         "modulus_of_the_same_material", "tests/test_disk_packing.py::test_fuller_radii_follow_the_"
                         "grading_by_area_and_fill_the_requested_area", "tests/test_disk_packing.py::test_graded_"
                         "beam_is_bonded_nearly_stress_free_and_cached", "benchmarks/bench_fatigue_beam.py"),
             "four_point_bending", "choice"),
    Decision("rollers of the bending beam", "walls touching the beam", "the disks under a 10 mm pad, guided in y "
             "(supports held, loading particles driven), free in x",
             "a rigid disk touching one particle crushed the bonds under it at a tenth of the strength; a pad "
             "spreads the load as the paper's walls do, and a guide in y only is a frictionless roller",
             (BEND + "test_damage_starts_at_the_bottom_between_the_loading_rollers",), "four_point_bending", "choice"),
    Decision("one fixture for both bending tests", "servo-controlled walls",
             "fixture='rockers', the default: rigid flat pads pivoting at the exact spans, one-sided, frictionless, "
             "the same for the monotonic (displacement) and the cyclic (force) test; mid-span held in x by symmetry; "
             "cycles need a seating load (load_min_ratio, by default SEATING = 0.1 on the rockers); 'pads' kept for "
             "the studies stored with it, which ask for it by name",
             "the pads fixture measures two specimens (E_f 1.80 GPa monotonic, 1.74–1.78 cyclic) and its supports "
             "pull the beam down at its ends (160 N at P = 157 N); the rocker pads carry their resultants at x₀ "
             "within 0.02 r, never pull, and give the same E_f in both tests (0.1 %)",
             (BEND + "test_rocker_rollers_make_one_specimen_for_both_tests_at_the_exact_spans_and_never_pull",),
             "four_point_bending", "choice"),
    Decision("FS_max of the beam", "1336.4 kPa with σ_t = c = 74 kPa (Table 2)", "Table 2 kept; FS_max ≈ 3 σ_t",
             "a section whose bonds cap tension at σ_t carries at most FS = 3 σ_t = 222 kPa; 1336 kPa is 18 σ_t, so "
             "the table's strengths or the thickness in Eq. (42) differ from what the text implies",
             ("benchmarks/bench_fatigue_beam.py",), "four_point_bending", "ambiguity"),
    Decision("calibrating the beam's strength by similarity", "FS_max = 1336.4 kPa from Table 2's bonds; no "
             "calibration stated", "beside the uncalibrated Table 2 beam, a calibrated one: σ_t, c, ū_n, ū_s (and "
             "the loading speed) × a factor (scaled_strengths), repeated factor ← factor · FS_paper / FS_max on the "
             "same specimen until FS_max is within 1 % of the paper's; k_n, k_s, E_c, the Paris law and the "
             "threshold as printed",
             "the bond law is homogeneous of degree one in (σ_t, c, ū, u) and the rest of the beam is linear, so the "
             "scaled monotonic test is the unscaled one times the factor (within 10⁻³ on the lattice; on the graded "
             "packings, whose settling forces do not scale, the first step misses by 1.9 and 1.2 % for seeds 0 and "
             "1 and the second lands within 0.06 %, with E_f 5.8 and 4.3 % below the uncalibrated one's)",
             (BEND + "test_scaled_strengths_give_the_similar_beam_under_a_scaled_load",
              BEND + "test_scaling_the_strengths_scales_the_monotonic_curve_by_the_same_factor",
              "benchmarks/bench_fatigue_beam.py"), "four_point_bending", "choice"),
    Decision("three stages of the modulus degradation", "the modulus falls in an initial, a middle and a final "
             "stage (Fig. 17a; the simulation's first stage faster than the test's); no bounds are given",
             "the stages are N/N_f in [0, 0.1], [0.1, 0.9] and [0.9, 1] (STAGES), each with the slope of a "
             "least-squares line of E_f/E_f,0 against N/N_f (stage_slopes); initial_over_middle > 1 is a fast "
             "first stage",
             "fixed fractions of the life compare runs of any length and any cycle jump; the figure's first stage "
             "ends within the first tenth of the life and its last begins in the last tenth",
             (BEND + "test_the_stage_slopes_are_those_of_a_piecewise_linear_degradation",
              "benchmarks/bench_fatigue_beam.py"), "four_point_bending", "choice"),
    Decision("failure damage of a bond", "D grows from D₀ to 1, where the yield and fatigue surfaces meet "
             "(Sec. 3.1, Fig. 4); a bond at D → 1 is not otherwise defined",
             "D_fail = 1 − 10⁻⁶ (bond_law.FAILURE_DAMAGE): a bond that reaches it is broken (the DEM removes it "
             "and logs a crack); the return computes 1 − D as (1 − D₀) e^{−κ} to full precision, holds F to the "
             "larger of the start's and the end state's surface size, and cannot fail for a bond short of D_fail; "
             "one whose iteration ends past it breaks in that step",
             "at D_fail the surfaces are 10⁻⁶ of their size (0.07 Pa for Table 2): the seed's final stage. Near "
             "D = 1, 1 − D taken from the rounded D kept too few digits for the return's tolerance, and beam "
             "runs stopped on bonds at D = 1 − 2·10⁻⁶: one in near-pure shear, and one pressed shut by its own "
             "dilatancy whose surface grew 62 × by friction, so that F's round-off exceeded the tolerance "
             "relative to the start state",
             (BOND + "test_a_bond_next_to_full_damage_in_near_pure_shear_returns_or_breaks",
              BOND + "test_a_nearly_broken_bond_pressed_shut_by_its_dilatancy_returns_in_one_step"),
             "four_point_bending", "choice"),
    Decision("ratcheting in the cycle jump", "a bond that yields in the sampled cycle gets no fatigue (E = 0 in "
             "Eq. 17); what it does during the jump is not addressed", "the paper's reading by default "
             "(plasticity='frozen': it stands still); plasticity='extrapolated' repeats the sampled cycle's plastic "
             "displacement in every skipped cycle (Eq. 22's damage, elastic displacement lowered like the fatigue "
             "displacements) and bounds N_jump by that damage rate too; settle=1 simulates one cycle after each "
             "jump before the next sample",
             "on the 5 mm beam at 77 % bonds yield in almost every cycle; frozen through the jumps, they make the "
             "life 1.5–4.3 times the cycle-by-cycle 1759 cycles (ΔD_jump 0.001–0.01); extrapolated with one "
             "settling cycle, the life converges to it from below: −26 %, −15 %, −4.8 % at ΔD_jump = 0.003, 0.001, "
             "0.0003 (699 simulated cycles). From 81 % up the beam fails by ratcheting in 2–3 cycles, which the "
             "frozen jump steps over (benchmark)",
             (BOND + "test_ratcheting_in_the_jump_repeats_the_sampled_plastic_increment_and_bounds_the_jump",
              "tests/test_fatigue_dem.py::test_bonds_record_their_plastic_flow_per_cycle_and_extrapolate_it_on_request",
              "benchmarks/bench_fatigue_beam.py"),
             "four_point_bending", "reconstruction"),
    Decision("damage tensor of seed 001", "σ = (I − D) C (ε − ε_res) with Chaboche's D from one normal and two "
             "shear damage variables in the crack axes; its entries are not printed",
             "D_xx,xx = d_n, D_yy,xx = D_zz,xx = d_n ν/(1 − ν), D_xy,xy = d_xy, D_xz,xz = d_xz, the rest zero; d_n "
             "acts only while the crack is open (e_n = σ_e,xx/C₁₁ > 0)",
             "the only such D for which a fully open crack (d_n = 1) carries no traction while the material beside "
             "it keeps its plane-stress stiffness (E along y and z, 2μ in yz shear); (I − D) C is then symmetric "
             "and the cracking strains are d_n e_n, d_xy γ₁, d_xz γ₂ (Nairn, Hammerquist & Aimene 2017)",
             (AD + "test_a_tension_crack_leaves_the_stiffness_along_the_crack_plane_untouched",
              AD + "test_a_closed_crack_carries_compression_and_never_fails_in_the_normal_direction",
              AD + "test_unloading_is_secant_back_to_the_origin"), "anisotropic_damage", "reconstruction"),
    Decision("softening and the crack band of seed 001", "softening laws whose areas are G_Ic and G_IIc; how the "
             "opening relates to a point's strain is not given (MPM particle size)",
             "the opening is smeared over the band width h, δ = h d e; h = the element's extent along the crack "
             "normal (projection), fixed at initiation, twice that on a symmetry line (the mirror completes the "
             "band: the sharp notch's and the DCB's ligament); a band wider than h_max = k M G_c/σ_c² (k = 2 "
             "linear, 1 exponential; M = E in mode I, μ in mode II) is refused with its limit",
             "with δ = h d e the energy per crack area is G_c whatever the mesh (bar of 1–64 elements: G_Ic A to "
             "4·10⁻⁶ by the work); beyond h_max a point snaps back on its own and the band dissipates more than G_c; "
             "with the single width on the ligament the half sharp notch counted the toughness twice and its 4000 "
             "element mesh cracked diffusely in 1300 elements and stopped at the peak",
             (CB + "test_bar_dissipates_the_toughness_per_crack_area_on_every_mesh",
              CB + "test_band_on_a_symmetry_line_counts_twice",
              CB + "test_an_element_wider_than_the_band_limit_is_refused_when_it_cracks",
              AD + "test_too_wide_a_band_is_refused_with_its_limit"), "anisotropic_damage", "reconstruction"),
    Decision("damage under a traction failure surface", "surfaces 0–3 described in words (cuboid: return normal to "
             "the surface; ovoid and coupled cuboid: towards the origin, d_n = d_xy = d_xz)",
             "each group of coupled directions shares one damage d, found from f(d) = 1 with the openings "
             "δᵢ = max(δᵢ,old, h d eᵢ) (false position, Illinois); cuboid: three groups, elliptical cylinder: normal "
             "+ one shear group (|(γ₁, γ₂)|), ovoid: (T_n/S_I)² + (T_t/S_II)² = 1, coupled cuboid: the largest "
             "ratio; the tangent is the consistent one by implicit differentiation",
             "damage growth along the secant (towards the origin) is what the seed describes for the coupled "
             "surfaces; for one direction it is the usual cohesive return; the consistent tangent matches finite "
             "differences to 1e-7",
             (AD + "test_tension_then_shear_follows_the_coupling_of_each_surface",
              AD + "test_tangent_is_consistent_on_the_softening_branch"), "anisotropic_damage", "reconstruction"),
    Decision("crack plane of a shear initiation", "the normal of the failure envelope at initiation fixes the crack "
             "normal", "tension: the direction of σ₁; shear ((σ₁ − σ₃)/2 ≥ τ_c): n = (v₁ + v₃)/√2, t₁ = (v₁ − v₃)/√2, "
             "eigenvector signs fixed (largest component positive) so the choice between the two planes of largest "
             "shear is the same on every machine; plane=True keeps n in the x–y plane",
             "the two planes of largest shear are equivalent; an unfixed eigenvector sign would pick either at random",
             (AD + "test_shear_initiation_takes_the_plane_of_largest_shear",
              AD + "test_plane_crack_normal_is_the_principal_direction_of_a_rotated_tension"),
             "anisotropic_damage", "choice"),
    Decision("dissipation of seed 001's model", "energies G_I, G_II tracked as history variables, method not given",
             "∫ Y dd with Y_n = C₁₁⟨e_n⟩₊²/2, Y_t = μγ²/2, the strain linear in the step and the damage solved at "
             "s = ¼, ½, ¾ too (trapezoid on four intervals)",
             "the thermodynamic dissipation of (AD.1); one trapezoid per step was 4.5 % high on a 64-element bar, "
             "four intervals 0.3 %; the work–energy budget closes to 0.5 % of G_Ic/h on a mixed path",
             (AD + "test_energy_budget_closes_on_a_mixed_path_with_unloading",
              CB + "test_bar_dissipates_the_toughness_per_crack_area_on_every_mesh"), "anisotropic_damage", "choice"),
    Decision("a prescribed crack plane", "the crack normal comes from the initiation law",
             "crack_normal=(…) fixes it where the path is known (the DCB ligament); the point cracks when its "
             "tractions on that plane leave the surface",
             "left to the initiation law, the arms' bending starts cracks with inclined normals ahead of the DCB's "
             "tip (normals 20–82° from y) and these fixed cracks lock the band: with 1 mm elements the force at δ = "
             "1.5 mm was 13.2 N against LEFM's 6.4 N and still rising",
             (AD + "test_prescribed_crack_plane_cracks_when_its_traction_reaches_the_strength",
              CB + "test_dcb_propagation_force_approaches_lefm_as_the_mesh_is_refined"), "anisotropic_damage",
             "choice"),
    Decision("seed 001 on the steel specimens of Ch. 7", "no parameters for a steel",
             "Table 7.1's E and ν, σ_c = 120 MPa, τ_c = 80 MPa, G_IIc = 2 G_Ic, G_Ic = 10 N/mm, ovoid, linear laws",
             "chosen so that the double notch peaks near Model I and II (about 10 kN); G_Ic is the model's "
             "regularisation parameter, as β and α are for Model I and II",
             ("benchmarks/bench_anisotropic_damage.py",), "anisotropic_damage", "choice"),
    Decision("pressure-dependent shear strength (seed 001)", "optional, with an iterative pressure loop",
             "not built", "none of the toolkit's problems needs it; the initiation and the surfaces are pressure "
             "independent", (AD + "test_shear_initiation_does_not_depend_on_pressure",), "anisotropic_damage",
             "choice"),
)


def markdown(decisions=DECISIONS) -> str:
    """The decisions as a Markdown table (topic, seed, ours, reason, pinned by, chapter)."""
    def cell(text: str) -> str:       # a bar inside a cell (|p|) would end it
        return text.replace("|", "\\|")

    rows = ["| topic | seed | ours | reason | pinned by | chapter |", "|---|---|---|---|---|---|"]
    for d in decisions:
        tests = "<br>".join(f"`{t.split('::')[-1]}`" if "::" in t else f"`{t}`" for t in d.tests)
        rows.append(f"| {cell(d.topic)} ({d.kind}) | {cell(d.seed)} | {cell(d.ours)} | {cell(d.reason)} | {tests} "
                    f"| {d.chapter} |")
    return "\n".join(rows)
