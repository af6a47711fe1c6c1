# The workspace pipeline: sweeps -> nominal CoG -> fitted curves -> 20-face workspace -> figures,
# two-pair and gravity-aware workspaces, locomotion runs, validation. Rules live in
# workflow/rules/<rule>.smk and call tensegrity.stages.<rule> (one module per rule file).
import os
import sys

# The compiled kernel runs the robots of a batch in OpenMP threads (numba's omp layer). An idle
# OpenMP thread spins by default, waiting for the next parallel step; the stages call the kernel
# thousands of times with Python in between, so with two threads the spinning thread doubled a
# job's CPU time and took a core from the other job (gravity: 15 -> 10 s CPU). Idle threads
# sleep instead. Every job inherits it; results do not depend on it (one robot per thread).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

from tensegrity.io.config import check_files as check_config_files, validate as validate_config

# Snakemake refuses an empty config/config.yaml (or one that is not a mapping) with a message that
# names no file; this names it. (An empty --configfile is refused by Snakemake's command line,
# before this file runs.)
if os.path.exists("config/config.yaml"):
    check_config_files(["config/config.yaml"])
configfile: "config/config.yaml"


# A bad config stops here, before any job runs, with a message naming the key. Snakemake's own
# YAML reader keeps the last of two equal keys: re-read every file it loaded (config/config.yaml
# and each --configfile) strictly, so that a duplicate key stops the run naming file and key.
check_config_files(workflow.configfiles)
config.update(validate_config(config))

report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"

wildcard_constraints:
    contact="|".join(CONTACTS),


include: "workflow/rules/sweep.smk"
include: "workflow/rules/nominal.smk"
include: "workflow/rules/fit.smk"
include: "workflow/rules/render.smk"
include: "workflow/rules/page.smk"
include: "workflow/rules/two_pair.smk"
include: "workflow/rules/gravity.smk"
include: "workflow/rules/locomotion.smk"
include: "workflow/rules/validate.smk"
include: "workflow/rules/study.smk"


rule all:
    input:
        expand("results/nominal/{contact}.nc", contact=CONTACTS),
        expand("results/curves/{contact}.nc", contact=CONTACTS),
        "results/curves/curves.json",
        "results/workspace.nc",
        rules.render_all.input,
        rules.two_pair_all.input,
        rules.page.output,
        rules.validate.output,
        rules.locomotion_all.input,
        rules.gravity_all.input,
    default_target: True


# A demonstration run that did not arrive does not stop the workflow (its file and path figures
# show what happened; validation check 6 fails), but the run must not look like a success.
onsuccess:
    from tensegrity.stages.validate import runs_warning  # numerical imports: only here

    text = runs_warning(expand("results/locomotion/{run}.nc", run=LOCO_RUNS))
    if text:
        print(text, file=sys.stderr)


# Snakemake's job rate limiter (at most 100 job starts a second, for cluster submission) ends every
# scheduling round by starting a 1 s threading.Timer that is not a daemon thread, so Python waited
# for the last one: every local run ended about 1 s after its last job. A local run needs no rate
# limit. (Snakemake 9 internals, `JobScheduler.job_rate_limiter`: left alone if they change.)
onstart:
    if not workflow.remote_exec and hasattr(getattr(workflow, "scheduler", None), "job_rate_limiter"):
        workflow.scheduler.job_rate_limiter = None
