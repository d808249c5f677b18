# The paper's conjectures as experiments with counts (Figures S4-S7; docs/conjectures.md).
# Included after common.smk and before the rule files: it adds its entries to the tables (KERNELS,
# DATASETS, FIGURES, NUMBERS, SCRIPTS) from which simulations.smk, figures.smk and report.smk
# generate the rules, so the rules have the shape of every other one.

# the two-disk orbits (plain tables) and the wedges under a force (walls+force), with logs (monodromy,
# the finder) and simulate_many's records; the polygons and disks under a force of Figure S6 (plain+force)
KERNELS["conjectures"] = ["plain:no-slip", "walls+force:no-slip", "plain+force:no-slip"]

CONJECTURE_DATASETS = {
    "conjectures_launch": dataset("conjectures", "launch.nc", "launch", "conjecture_launch",
                                  lambda: {"common": stability_common(), "run": section("conjectures.launch")},
                                  ENSEMBLE),
    "conjectures_census": dataset("conjectures", "census.nc", "census", "conjecture_census",
                                  lambda: {"common": stability_common(), "run": section("conjectures.census")},
                                  ENSEMBLE),
    "conjectures_accessible": dataset("conjectures", "accessible.nc", "accessible", "conjecture_accessible",
                                      lambda: {"common": stability_common(), "run": section("conjectures.accessible")},
                                      ENSEMBLE),
    "conjectures_invariant": dataset("conjectures", "invariant.nc", "invariant", "conjecture_invariant",
                                     lambda: {"common": stability_common(), "run": section("conjectures.invariant")},
                                     ENSEMBLE),
}
CONJECTURE_FIGURES = {
    "figS4_launch_classes": figure("Conjectures", {"launch": "conjectures_launch"}),
    "figS5_periodic_census": figure("Conjectures", {"census": "conjectures_census"}),
    "figS6_accessible_pairs": figure("Conjectures", {"accessible": "conjectures_accessible"}),
    "figS7_invariant_regions": figure("Conjectures", {"invariant": "conjectures_invariant"}),
}
DATASETS.update(CONJECTURE_DATASETS)
FIGURES.update(CONJECTURE_FIGURES)
NUMBERS["conjectures"] = figure(None, {"launch": "conjectures_launch", "census": "conjectures_census",
                                       "accessible": "conjectures_accessible",
                                       "invariant": "conjectures_invariant"})
SCRIPTS.update({name: spec["script"] for name, spec in CONJECTURE_DATASETS.items()})
SCRIPTS.update({name: name for name in CONJECTURE_FIGURES})
SCRIPTS["numbers_conjectures"] = "numbers_conjectures"
