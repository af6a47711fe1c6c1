rule map:
    """Map the canonical workspaces to all 20 faces with the symmetry group."""
    input:
        expand("results/nominal/{contact}.nc", contact=CONTACTS),
    output:
        "results/workspace.nc",
    log:
        "results/logs/map.log",
    priority: 35  # feeds the locomotion runs
    localrule: True
    script:
        "../scripts/map.py"
