# The paper's pulse studies (Figs 4-7): no record files needed.


rule pulse_overturn:
    output:
        f"{JOBS}/pulses/overturn-{{shape}}.h5",
    params:
        p=lambda wc: pipeline.params_pulse_overturn(config, wc.shape),
    resources:
        **RESOURCES["pulse_overturn"],
    group:
        "pulses"
    benchmark:
        "results/benchmarks/pulse_overturn/{shape}.tsv"
    log:
        "logs/pulse_overturn/{shape}.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/pulse_overturn.py"


rule pulse_maps:
    output:
        f"{JOBS}/pulses/maps-{{src}}.h5",
    params:
        p=lambda wc: pipeline.params_pulse_maps(config, wc.src),
    threads: MAP_THREADS
    resources:
        **RESOURCES["pulse_maps"],
    group:
        "pulses"
    benchmark:
        "results/benchmarks/pulse_maps/{src}.tsv"
    log:
        "logs/pulse_maps/{src}.log",
    conda:
        "../envs/isorock.yaml"
    script:
        "../scripts/pulse_maps.py"
