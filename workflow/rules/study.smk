# Design studies (config/studies/<name>.yaml, docs/datasets.md "Design studies"): chosen with
# --config study=<name> and built by the target `study`; never part of `all`. One job per chunk of
# designs (one batched simulation each); a chunk file that exists is never recomputed.
from tensegrity.io.settings import params as params_of
from tensegrity.io import study_config
from tensegrity.studies import spec as study_spec

STUDY = config.get("study") or ""
STUDY_LIMIT = int(config.get("study_limit") or 0)
if STUDY:
    # a bad study stops here, before any job runs, naming the file and the key
    STUDY_SPEC = study_config.load(STUDY, base=params_of(config), dt=config["sim"]["dt"])
    STUDY_DIR = f"results/studies/{STUDY}"
    STUDY_CHUNKS = expand(f"{STUDY_DIR}/chunks/chunk{{chunk:04d}}.nc",
                          chunk=range(study_spec.n_chunks(STUDY_SPEC, STUDY_LIMIT)))
    STUDY_FIGURES = [f"{STUDY_DIR}/figures/sensitivity.png"] + (
        [f"{STUDY_DIR}/figures/response.png"] if STUDY_SPEC["workspace"]["enabled"] else []) + (
        [f"{STUDY_DIR}/figures/robustness.png"] if STUDY_SPEC["roll"]["enabled"] else [])
    STUDY_RES = STUDY_SPEC["resources"]


def _no_study(*_):
    raise ValueError("config key study: name a study, e.g. --config study=stiffness_pretension "
                     "(the files in config/studies/)")


if STUDY:

    rule study_chunk:
        """One chunk of designs: the workspace (and roll sequence) of every design, one batch."""
        output:
            f"{STUDY_DIR}/chunks/chunk{{chunk}}.nc",
        params:
            cfg=cfg("study_chunk"),
            study=study_spec.chunk_study(STUDY_SPEC),
            limit=STUDY_LIMIT,
        log:
            f"results/logs/studies/{STUDY}/chunk{{chunk}}.log",
        benchmark:
            f"results/benchmarks/studies/{STUDY}/chunk{{chunk}}.tsv"
        wildcard_constraints:
            chunk=r"\d{4}",
        threads: STUDY_RES["threads"]
        resources:
            mem_mb=STUDY_RES["mem_mb"],
            runtime=STUDY_RES["runtime"],
        script:
            "../scripts/study_chunk.py"

    rule study_merge:
        """All chunks concatenated along `design`: designs.nc."""
        input:
            STUDY_CHUNKS,
        output:
            f"{STUDY_DIR}/designs.nc",
        params:
            cfg=cfg("study_merge"),
            study=study_spec.chunk_study(STUDY_SPEC),
        log:
            f"results/logs/studies/{STUDY}/merge.log",
        localrule: True
        script:
            "../scripts/study_merge.py"

    rule study_analyse:
        """Sensitivity indices, best designs and the study's figures."""
        input:
            f"{STUDY_DIR}/designs.nc",
        output:
            nc=f"{STUDY_DIR}/analysis.nc",
            figures=[report(f, category="Design study", caption="../report/study.rst") for f in STUDY_FIGURES],
        params:
            cfg=cfg("study_analyse"),
            study={k: v for k, v in STUDY_SPEC.items() if k != "resources"},
        log:
            f"results/logs/studies/{STUDY}/analyse.log",
        localrule: True
        script:
            "../scripts/study_analyse.py"


rule study:
    """The study named by --config study=<name> (not part of `all`)."""
    input:
        [f"{STUDY_DIR}/analysis.nc"] + STUDY_FIGURES if STUDY else _no_study,
    localrule: True
