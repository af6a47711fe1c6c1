"""Checks of the pipeline's results (issue 5). The checks return numbers and statuses:
`checks` (statics, mapping, time step and `run_checks`), `paper`, `grounded`, on the nominal
CoG of `nominals`, with the statuses and settings of `common`. `summary` words the results and
`report` writes validation.nc, summary.md and summary.html (`report.run_stage`, the stage)."""
