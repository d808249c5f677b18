# Figure rules: each figure script reads datasets with xarray and draws with noslipsim.plot; it
# never simulates.  Outputs are figures/figNN_topic.pdf and .png (byte-stable), the PNG
# registered for the HTML report (`snakemake --report report.html`) with a caption file in
# workflow/report/.  One section per subject.


# ---------------------------------------------------------------- galton (Figures 2, 3, S1)
rule fig02_galtonboard:
    input:
        orbits="results/galton/orbits.nc",
    output:
        pdf="figures/fig02_galtonboard.pdf",
        png=report("figures/fig02_galtonboard.png", caption="../report/fig02_galtonboard.rst",
                   category="Galton board"),
    log:
        log_file("fig02_galtonboard"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig02_galtonboard.py"


rule fig03_normal:
    input:
        distribution="results/galton/distribution.nc",
    output:
        pdf="figures/fig03_normal.pdf",
        png=report("figures/fig03_normal.png", caption="../report/fig03_normal.rst", category="Galton board"),
    params:
        bins=config["galton"]["distribution"]["bins"],
    log:
        log_file("fig03_normal"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig03_normal.py"


rule figS1_galton_trapping:
    input:
        arrivals="results/galton/arrivals.nc",
        sweep="results/galton/radius_sweep.nc",
    output:
        pdf="figures/figS1_galton_trapping.pdf",
        png=report("figures/figS1_galton_trapping.png", caption="../report/figS1_galton_trapping.rst",
                   category="Galton board"),
    log:
        log_file("figS1_galton_trapping"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/figS1_galton_trapping.py"


# ---------------------------------------------------------------- orbits (Figures 1, 4, 5, 6, 8, 16)

# ---------------------------------------------------------------- portraits (Figures 10-13)

# ---------------------------------------------------------------- stability (Figures 7, 9, 14, 15)
