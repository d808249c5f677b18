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
        histogram=config["galton"]["histogram"],
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
rule fig01_specnoslip:
    input:
        specnoslip="results/orbits/specnoslip.nc",
    output:
        pdf="figures/fig01_specnoslip.pdf",
        png=report("figures/fig01_specnoslip.png", caption="../report/fig01_specnoslip.rst", category="Orbits"),
    log:
        log_file("fig01_specnoslip"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig01_specnoslip.py"


rule fig04_pentagons:
    input:
        pentagons="results/orbits/pentagons.nc",
    output:
        pdf="figures/fig04_pentagons.pdf",
        png=report("figures/fig04_pentagons.png", caption="../report/fig04_pentagons.rst", category="Orbits"),
    log:
        log_file("fig04_pentagons"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig04_pentagons.py"


rule fig05_bouncingball:
    input:
        bounce="results/orbits/bounce.nc",
    output:
        pdf="figures/fig05_bouncingball.pdf",
        png=report("figures/fig05_bouncingball.png", caption="../report/fig05_bouncingball.rst", category="Orbits"),
    log:
        log_file("fig05_bouncingball"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig05_bouncingball.py"


rule fig06_newwedge:
    input:
        newwedge="results/orbits/newwedge.nc",
    output:
        pdf="figures/fig06_newwedge.pdf",
        png=report("figures/fig06_newwedge.png", caption="../report/fig06_newwedge.rst", category="Orbits"),
    log:
        log_file("fig06_newwedge"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig06_newwedge.py"


rule fig08_noslipstablesinai:
    input:
        twodisks="results/orbits/twodisks.nc",
    output:
        pdf="figures/fig08_noslipstablesinai.pdf",
        png=report("figures/fig08_noslipstablesinai.png", caption="../report/fig08_noslipstablesinai.rst", category="Orbits"),
    log:
        log_file("fig08_noslipstablesinai"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig08_noslipstablesinai.py"


rule fig16_3dbounce:
    input:
        sphere="results/orbits/sphere.nc",
    output:
        pdf="figures/fig16_3dbounce.pdf",
        png=report("figures/fig16_3dbounce.png", caption="../report/fig16_3dbounce.rst", category="Orbits"),
    log:
        log_file("fig16_3dbounce"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig16_3dbounce.py"



# ---------------------------------------------------------------- portraits (Figures 10-13)
rule fig10_phaseportraits:
    input:
        portraits="results/portraits/phaseportraits.nc",
    output:
        pdf="figures/fig10_phaseportraits.pdf",
        png=report("figures/fig10_phaseportraits.png", caption="../report/fig10_phaseportraits.rst",
                   category="Phase portraits"),
    log:
        log_file("fig10_phaseportraits"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig10_phaseportraits.py"


rule fig11_vppregpoly:
    input:
        portraits="results/portraits/polygons.nc",
    output:
        pdf="figures/fig11_vppregpoly.pdf",
        png=report("figures/fig11_vppregpoly.png", caption="../report/fig11_vppregpoly.rst",
                   category="Phase portraits"),
    log:
        log_file("fig11_vppregpoly"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig11_vppregpoly.py"


rule fig12_lorentzgamma:
    input:
        portraits="results/portraits/sinai_gamma.nc",
        islands="results/portraits/islands.nc",
    output:
        pdf="figures/fig12_lorentzgamma.pdf",
        png=report("figures/fig12_lorentzgamma.png", caption="../report/fig12_lorentzgamma.rst",
                   category="Phase portraits"),
    log:
        log_file("fig12_lorentzgamma"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig12_lorentzgamma.py"


rule fig13_VPPforce:
    input:
        portraits="results/portraits/hex_force.nc",
    output:
        pdf="figures/fig13_VPPforce.pdf",
        png=report("figures/fig13_VPPforce.png", caption="../report/fig13_VPPforce.rst",
                   category="Phase portraits"),
    log:
        log_file("fig13_VPPforce"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig13_VPPforce.py"


# ---------------------------------------------------------------- stability (Figures 7, 9, 14, 15)
rule fig07_wedge:
    input:
        orbits="results/stability/wedge_orbits.nc",
    output:
        pdf="figures/fig07_wedge.pdf",
        png=report("figures/fig07_wedge.png", caption="../report/fig07_wedge.rst", category="Stability"),
    log:
        log_file("fig07_wedge"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig07_wedge.py"


rule fig09_2perunstablea:
    input:
        orbits="results/stability/wedge_perturbed.nc",
    output:
        pdf="figures/fig09_2perunstablea.pdf",
        png=report("figures/fig09_2perunstablea.png", caption="../report/fig09_2perunstablea.rst",
                   category="Stability"),
    log:
        log_file("fig09_2perunstablea"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig09_2perunstablea.py"


rule fig14_2perunstable:
    input:
        orbits="results/stability/launch_orbits.nc",
        scan="results/stability/launch_scan.nc",
    output:
        pdf="figures/fig14_2perunstable.pdf",
        png=report("figures/fig14_2perunstable.png", caption="../report/fig14_2perunstable.rst",
                   category="Stability"),
    log:
        log_file("fig14_2perunstable"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig14_2perunstable.py"


rule fig15_stabexp:
    input:
        noforce="results/stability/grid_noforce.nc",
        force="results/stability/grid_force.nc",
        theta="results/stability/grid_theta.nc",
    output:
        pdf="figures/fig15_stabexp.pdf",
        png=report("figures/fig15_stabexp.png", caption="../report/fig15_stabexp.rst", category="Stability"),
    params:
        sketch=config["stability"]["grids"]["sketch"],
    log:
        log_file("fig15_stabexp"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/fig15_stabexp.py"
