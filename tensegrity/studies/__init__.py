"""Design studies (issue 12): many robot designs through the same simulation, as configured in
config/studies/<name>.yaml. `spec` (the study file, its design matrix and chunks), `evaluate`
(per-design workspace and roll sequence, batched), `results` (the datasets), `analysis`
(SALib indices, best designs, success rates). Imports physics, workspace, locomotion and io;
only the entry points (`study_stages`, `cli`) import it."""
