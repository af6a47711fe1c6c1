# The workspace pipeline: sweeps -> nominal CoG -> fitted curves -> 20-face workspace
# -> figures. Rules live in workflow/rules/<stage>.smk and call tensegrity.stages.
from tensegrity.io.config import validate as validate_config
from tensegrity.stages import stage_config  # the config sections each rule passes

configfile: "config/config.yaml"


# A bad config stops here, before any job runs, with a message naming the key.
config.update(validate_config(config))

CONTACTS = config["sweep"]["contacts"]
PAIRS = config["sweep"]["pairs"]

report: "workflow/report/workflow.rst"

wildcard_constraints:
    contact="|".join(CONTACTS),


include: "workflow/rules/sweep.smk"
include: "workflow/rules/nominal.smk"
include: "workflow/rules/fit.smk"
include: "workflow/rules/map.smk"
include: "workflow/rules/render.smk"
include: "workflow/rules/validate.smk"
include: "workflow/rules/locomotion.smk"


rule all:
    input:
        expand("results/nominal/{contact}.nc", contact=CONTACTS),
        expand("results/curves/{contact}.nc", contact=CONTACTS),
        "results/curves/curves.json",
        "results/workspace.nc",
        rules.render_all.input,
        rules.validate.output,
        rules.locomotion_all.input,
    default_target: True
