# Figure rules, generated from FIGURES (common.smk): each figure script reads datasets with
# noslipsim.plot.load_figure_data and draws with noslipsim.plot; it never simulates, and it refuses
# an empty dataset or panel.  Outputs are figures/figNN_topic.pdf and .png (byte-stable), the PNG
# registered for the HTML report (`snakemake --report report.html`) with a caption file in
# workflow/report/.  `params:` carry only what the drawing depends on (thresholds of a
# classification, bin widths): changing one redraws without rerunning a simulation.


for name, spec in FIGURES.items():

    rule:
        name:
            name
        input:
            **inputs_of(spec),
        output:
            pdf=f"figures/{name}.pdf",
            png=report(f"figures/{name}.png", caption=f"../report/{name}.rst", category=spec["category"]),
        params:
            **spec["params"](),
        log:
            log_file(name),
        threads: 1
        conda:
            SOFTWARE
        script:
            script_of(vars().get("rule"), name)


rule evidence:
    # The Galton evidence alone (Figure S2 and its numbers, config galton.evidence): the longest
    # Galton run, `snakemake -j2 evidence`.  `snakemake -j2` (rule all) builds it too.
    input:
        figure_files("figS2_galton_evidence"),
        "results/numbers/evidence.json",
