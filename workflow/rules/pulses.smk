# The paper's pulse studies (Figs 4-7): no record files needed.


rule pulse_overturn:
    output:
        f"{JOBS}/pulses/overturn-{{shape}}.h5",
    params:
        p=lambda wc: pipeline.params_pulse_overturn(config, wc.shape),
    log:
        "logs/pulse_overturn/{shape}.log",
    script:
        "../scripts/pulse_overturn.py"


rule pulse_maps:
    output:
        f"{JOBS}/pulses/maps-{{src}}.h5",
    params:
        p=lambda wc: pipeline.params_pulse_maps(config, wc.src),
    threads: MAP_THREADS
    log:
        "logs/pulse_maps/{src}.log",
    script:
        "../scripts/pulse_maps.py"
