rule render:
    """Fig. 1 (the robot, numbered), Fig. 4 (actuator pairs), Fig. 5 (support frame); Fig. 6:
    the CoG point cloud and nominal CoGs of one pair on the equilateral face; Fig. 7: the
    kinematic workspace of every contact case; the CoG region one pair and two pairs reach, with
    the support triangle, of every contact case (one job: each job would pay the renderer's
    start-up again, about 2 s)."""
    input:
        sweep=[] if NOMINAL_STATICS else f"results/sweeps/{FIG6_CONTACT}/pair{FIG6_PAIR:02d}.nc",  # statics: none
        curves=expand("results/curves/{contact}.nc", contact=CONTACTS),
        nominal=expand("results/nominal/{contact}.nc", contact=CONTACTS),
        two_pair=expand("results/two_pair/{contact}.nc", contact=CONTACTS),
    output:
        fig1=report("results/figures/fig1_robot.png", caption="../report/fig1.rst", category="Figures", subcategory="robot"),
        fig4=report("results/figures/fig4_pairs.png", caption="../report/fig4.rst", category="Figures", subcategory="robot"),
        fig5=report("results/figures/fig5_support_frame.png", caption="../report/fig5.rst", category="Figures", subcategory="robot"),
        fig6=report("results/figures/fig6_cog_cloud.png", caption="../report/fig6.rst", category="Figures",
                    subcategory="CoG cloud"),
        fig7=[report(f"results/figures/fig7_workspace_{contact}.png", caption="../report/fig7.rst",
                     category="Figures", subcategory=contact) for contact in CONTACTS],
        two_pair=[report(f"results/figures/two_pair_{contact}.png", caption="../report/two_pair.rst",
                         category="Figures", subcategory=contact) for contact in CONTACTS],
    params:
        cfg=cfg("robot_figures"),
        fig6_nominal=f"results/nominal/{FIG6_CONTACT}.nc",
    log:
        "results/logs/render.log",
    benchmark:
        "results/benchmarks/render.tsv"
    priority: 20
    localrule: True
    script:
        "../scripts/render.py"


rule render_prototype:
    """Fig. 12 simulated: the prototype at the start, after roll 1 and after roll 2 of IV.B, the
    voltages and the resting face over time (results/validation/prototype.nc)."""
    input:
        prototype="results/validation/prototype.nc",
    output:
        fig12=report("results/figures/fig12_prototype.png", caption="../report/fig12.rst", category="Figures",
                     subcategory="prototype"),
    params:
        cfg=cfg("prototype_figure"),
    log:
        "results/logs/render_prototype.log",
    benchmark:
        "results/benchmarks/render_prototype.tsv"
    priority: 20
    localrule: True
    script:
        "../scripts/render_prototype.py"


rule render_all:
    input:
        rules.render.output,
        rules.render_prototype.output,
