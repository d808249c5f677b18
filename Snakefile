# noslipsim: the paper's figures from simulations.
#   snakemake -j2                      paper size (config/config.yaml)
#   snakemake -j2 --directory .test    reduced run (.test/config/config.yaml), into .test/
#   snakemake --report report.html     every figure with its caption, one HTML file
# Layout and how to add a figure: workflow/README.md; the config keys: config/README.md.
from snakemake.utils import min_version

min_version("8.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/conjectures.smk"
include: "workflow/rules/simulations.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/report.smk"


rule all:
    input:
        all_targets(),
    default_target: True
