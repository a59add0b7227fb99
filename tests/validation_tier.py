"""The validation tier: the physical claims CI checks against an experiment, a benchmark or
an exact solution, each at the cheapest resolution at which it means something (issue 51).

Every entry names a CI test (not `slow`) and the claim it carries; conftest.py marks them
`validation`, so ``python -m pytest -m validation`` runs the tier alone (about 8 min on
two cores). Their slow versions, at the resolutions the documented figures come from, run
with ``python -m pytest -m slow`` (docs/validation.md, "The validation tier").
tests/test_validation_tier.py checks that every entry is a test and is in the docs' table."""

TIER = {
    # bodies
    "tests/test_archimedes_release.py::test_a_released_box_settles_at_archimedes_draft_quick":
        "Archimedes in 2D: a box let go below, above and rolled settles at its draft, upright",
    "tests/test_archimedes_release.py::test_a_released_cube_settles_at_archimedes_draft_in_3d":
        "Archimedes in 3D: a cube let go 40 % deeper settles at its draft",
    "tests/test_water_entry.py::test_a_cylinder_enters_the_water_quick":
        "water entry: the cylinder sinks, stops and rises; no water in it",
    # free-surface flows against experiments
    "tests/test_validation.py::test_dam_break_front_and_column_height":
        "dam break: the front against Koshizuka & Oka, the column against Martin & Moyce",
    "tests/test_buchner.py::test_p1_impact_time_at_coarse_resolution":
        "dam break: P1's impact time against Buchner's experiment",
    "tests/test_buchner.py::test_p1_and_p2_under_dfsph":
        "dam break, DFSPH: P1 and P2 against Buchner's experiment",
    "tests/test_buchner.py::test_p1_and_p2_with_the_riemann_formulation":
        "dam break, Riemann formulation: P1 and P2 against Buchner's experiment",
    "tests/test_kleefsman.py::test_surge_reaches_the_box_coarse":
        "SPHERIC test 2 (3D): water heights, arrival and impact times and P3 against Kleefsman et al.",
    "tests/test_dfsph.py::test_dam_break_stays_incompressible_and_runs_quick":
        "DFSPH dam break: incompressible, its front against Koshizuka & Oka",
    # waves
    "tests/test_solitary_wave.py::test_a_solitary_wave_runs_down_the_flume_quick":
        "a solitary wave keeps its height and Boussinesq's celerity",
    "tests/test_waves.py::test_the_piston_makes_theorys_waves_quick":
        "a piston wave maker makes first-order theory's height and wavelength",
    # internal flows against exact solutions and a benchmark
    "tests/test_validation.py::test_poiseuille_profile_and_convergence": "Poiseuille against Morris' series",
    "tests/test_validation.py::test_couette_profile": "Couette against Morris' series",
    "tests/test_validation.py::test_taylor_green_beats_pysph_edac": "Taylor-Green against the exact vortex",
    "tests/test_cylinder.py::test_drag_at_coarse_resolution": "the cylinder's drag against Schaefer & Turek (Re 20)",
    "tests/test_open_boundaries.py::test_the_open_channel_reaches_poiseuilles_parabola":
        "an open channel reaches Poiseuille's parabola",
    "tests/test_open_boundary_orientation.py::test_a_stream_started_from_rest_flows_along_the_inward_normal":
        "open boundaries on every face: the stream's exact speed",
    # pressure
    "tests/test_validation.py::test_hydrostatic_tank_dummy_walls": "a tank's pressure is hydrostatic",
    "tests/test_dfsph_3d_pressure.py::test_dfsph_builds_the_hydrostatic_pressure_of_a_3d_tank_from_zero":
        "DFSPH in 3D builds a tank's hydrostatic pressure from zero",
    "tests/test_dfsph_3d_pressure.py::test_released_column_has_the_potential_flow_pressure":
        "DFSPH in 3D: a released column's pressure is potential flow's",
    "tests/test_dfsph_3d_pressure.py::test_dfsph_floor_pressure_agrees_with_wcsph_in_the_3d_dam_break":
        "DFSPH's 3D floor pressure is WCSPH's",
    # two phases and surface tension
    "tests/test_multiphase.py::test_laplace_pressure_of_a_drop_at_rest":
        "Laplace: a drop's pressure jump against sigma / R",
    "tests/test_rising_bubble.py::test_rising_bubble_test_case_1_quick":
        "Hysing et al.'s rising bubble (ratio 10): the rise velocity's maximum and its time",
    # gas dynamics
    "tests/test_gas.py::test_sod_plateaus_and_shock": "Sod's shock tube against the exact Riemann solution",
    "tests/test_gas.py::test_sedov_blast_follows_the_similarity_law": "Sedov's blast against Taylor's similarity law",
}
