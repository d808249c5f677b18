# The paper's stated numbers, computed from the datasets.  Each subject of NUMBERS (common.smk) has a
# rule numbers_<subject> writing results/numbers/<subject>.json ({key: record}, see
# noslipsim.plot.numbers); rule numbers gathers the fragments into figures/numbers.json and the
# markdown table figures/numbers.md that the README shows.


rule numbers:
    input:
        number_fragments(),
    output:
        json="figures/numbers.json",
        table="figures/numbers.md",
    log:
        log_file("numbers"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/numbers.py"


for subject, spec in NUMBERS.items():

    rule:
        name:
            f"numbers_{subject}"
        input:
            **inputs_of(spec),
        output:
            numbers=f"results/numbers/{subject}.json",
        params:
            **spec["params"](),
        log:
            log_file(f"numbers_{subject}"),
        threads: 1
        conda:
            SOFTWARE
        script:
            script_of(vars().get("rule"), f"numbers_{subject}")


rule readings:
    # Figure 15 under every reading a referee would try (docs/analysis.md): `snakemake -j2 readings`.
    input:
        readings=dataset_file("stability_readings"),
    output:
        table="results/stability/readings.md",
    params:
        min_run=config["stability"]["readings"]["min_run"],
    log:
        log_file("readings"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/readings_table.py"
