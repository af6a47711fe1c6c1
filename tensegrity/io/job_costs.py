"""What the pipeline's largest jobs would cost, estimated from the configuration before any job
runs: the memory of the samples a job holds and the time steps it simulates (`Cost`). A job over
a limit would fail (out of memory) or run for days only after Snakemake deleted its old outputs;
`io.cross_checks` refuses a configuration whose sweep, two-pair or gravity job is over a limit,
`io.study_config` a study whose chunk job is, naming the key that costs most (`over_limit`).

The limits, for one job: MEMORY_LIMIT, 8 GiB of recorded samples (the rules ask for 1-2 GB, a
laptop has 8-16 GiB; the default pipeline's largest job holds 0.8 GiB); STEP_LIMIT, 1e11
robot-steps (time steps of one robot: about 10 h on one core at the 3-5 M robot-steps per second
the simulator makes, 1000 times the default pipeline's largest job, the gravity-aware workspace).

The estimates (robots x recorded samples x bytes per robot and sample; robots x simulated
seconds / sim.dt):
- sweep: one job, the contact cases of sweep.contacts one after the other, each a batch of one
  robot per pair of sweep.pairs through sweep.settle + levels x sweep.hold s, a sample every
  sim.record_every x sim.dt; STAIRCASE_BYTES per robot and sample (the simulator's record of 54
  numbers and the nodes, frames and file made from it: 1.44 kB measured, the peak resident memory
  of `tensegrity stage sweep` with sweep.hold 1 s and 5 s);
- two_pair: one robot per stabiliser orbit of the combinations of two_pair.pairs (22 on the
  equilateral face, 38 on the isosceles one, of all 66), levels^2 x two_pair.hold s, a sample
  every two_pair.record_every x sim.dt, STAIRCASE_BYTES (1.08 kB measured);
- gravity: both contact cases, len(gravity.pairs) robots per slope and heading (one heading on
  flat ground), a sample per locomotion.interval through gravity.settle, the ramp to
  gravity.max_pressure at locomotion.ramp_rate, 1 s at the top and up to 5 s of holds
  (`workspace.gravity.ramp_levels`, MAX_HOLD), GRAVITY_BYTES (16 numbers, allocated at the start);
- study chunk: chunk_size x contacts x pairs robots through levels x hold s, holding a block of
  0.1 s of samples at a time (`studies.evaluate`), STAIRCASE_BYTES; the roll sequence is not
  counted (its length is bounded by the `locomotion` settings).
"""

from __future__ import annotations

import copy
import functools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

MEMORY_LIMIT = 8 * 2**30  # bytes of recorded samples held by one job
STEP_LIMIT = 1e11  # robot-steps of one job
STAIRCASE_BYTES = 1536  # per robot and recorded sample: sweeps, two-pair sweeps, study chunks
GRAVITY_BYTES = 16 * 8  # per robot and ramp interval: the gravity-aware workspace's records
GRAVITY_TOP, GRAVITY_HOLDS = 1.0, 5.0  # s: workspace.gravity.HOLD and MAX_HOLD
STUDY_BLOCK = 0.1  # s of samples a study chunk holds at once (studies.evaluate._blocks)


@dataclass(frozen=True)
class Cost:
    """One job: `job` names it; robot_seconds simulated in all (s), dt the time step (s);
    samples, the robot-samples it holds at once, of `sample_bytes` each; `detail` says how the
    numbers follow from the keys."""

    job: str
    robot_seconds: float
    dt: float
    samples: float
    sample_bytes: int
    detail: str

    @property
    def memory(self) -> float:
        return self.samples * self.sample_bytes

    @property
    def steps(self) -> float:
        return self.robot_seconds / self.dt

    def burden(self) -> float:
        """The larger of memory / MEMORY_LIMIT and steps / STEP_LIMIT (over 1: refused)."""
        return max(self.memory / MEMORY_LIMIT, self.steps / STEP_LIMIT)


def _size(n: float) -> str:
    units = ("B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB")
    k = min(len(units) - 1, max(0, int(math.log(max(n, 1.0), 1024))))
    return f"{n / 1024**k:.3g} {units[k]}"


def sweep(cfg: Mapping) -> Cost:
    s, dt, every = cfg["sweep"], float(cfg["sim"]["dt"]), int(cfg["sim"]["record_every"])
    robots, contacts = len(s["pairs"]), len(s["contacts"])
    secs = float(s["settle"]) + len(s["levels"]) * float(s["hold"])
    samples = robots * secs / (every * dt)
    return Cost(
        "a sweep job",
        contacts * robots * secs,
        dt,
        samples,
        STAIRCASE_BYTES,
        f"{robots} robots (sweep.pairs) x {secs:.3g} s (sweep.settle + {len(s['levels'])} sweep.levels x "
        f"sweep.hold), a sample every {every * dt:g} s (sim.record_every x sim.dt), for each of {contacts} "
        "contact case(s) (sweep.contacts) in turn",
    )


@functools.lru_cache(maxsize=64)
def _orbits(pairs: tuple[int, ...], contact: str) -> int:
    from ..physics import topology as topo
    from ..workspace import two_pair as tp

    return len(tp.representatives(topo.face_number(topo.CONTACT_FACES[contact]), tp.combos_of(pairs)))


def two_pair(cfg: Mapping) -> Cost:
    s, dt = cfg["two_pair"], float(cfg["sim"]["dt"])
    robots = [_orbits(tuple(sorted(s["pairs"])), c) for c in cfg["sweep"]["contacts"]]
    secs = len(s["levels"]) ** 2 * float(s["hold"])
    interval = int(s["record_every"]) * dt
    return Cost(
        "the two-pair job",
        sum(robots) * secs,
        dt,
        max(robots, default=0) * secs / interval,
        STAIRCASE_BYTES,
        f"{' then '.join(map(str, robots))} robots (the combinations of two_pair.pairs, one per orbit, on "
        f"each of sweep.contacts in turn) x {secs:.3g} s ({len(s['levels'])}^2 two_pair.levels x "
        f"two_pair.hold), a sample every {interval:g} s (two_pair.record_every x sim.dt)",
    )


def gravity(cfg: Mapping) -> Cost:
    g, loc, dt = cfg["gravity"], cfg["locomotion"], float(cfg["sim"]["dt"])
    interval = float(loc["interval"])

    def n(seconds: float) -> float:  # intervals, as ramp_levels counts them (huge: no rounding)
        x = seconds / interval - 1e-9
        return math.ceil(x) if x < 1e15 else x

    ramp = n(float(g["max_pressure"]) / float(loc["ramp_rate"]))
    samples = n(float(g["settle"])) + ramp + n(GRAVITY_TOP) + n(GRAVITY_HOLDS)
    cases = sum(1 if float(a) == 0 else len(g["headings"]) for a in g["slopes"])
    robots = len(g["pairs"]) * cases
    return Cost(
        "the gravity job",
        2 * robots * samples * interval,
        dt,
        robots * samples,
        GRAVITY_BYTES,
        f"{robots} robots (gravity.pairs x gravity.slopes x gravity.headings) for each of 2 contact cases in "
        f"turn x {samples:.6g} "
        f"intervals of locomotion.interval = {interval:g} s (gravity.settle, the ramp to gravity.max_pressure "
        f"at locomotion.ramp_rate, {GRAVITY_TOP:g} s at the top, up to {GRAVITY_HOLDS:g} s of holds)",
    )


def study_chunk(study: Mapping, dt: float) -> Cost:
    ws = study["workspace"]
    if not ws["enabled"]:
        return Cost("a chunk job", 0.0, dt, 0.0, STAIRCASE_BYTES, "no workspace")
    if ws["method"] == "statics":  # no simulation: a few kB per design
        return Cost("a chunk job", 0.0, dt, 0.0, STAIRCASE_BYTES, "workspace.method statics")
    robots = int(study["chunk_size"]) * len(ws["contacts"]) * len(ws["pairs"])
    secs = len(ws["levels"]) * float(ws["hold"])
    interval = int(ws["sample_every"]) * dt
    held = min(round(float(ws["hold"]) / interval), max(1, round(STUDY_BLOCK / interval)))
    return Cost(
        "a chunk job",
        robots * secs,
        dt,
        robots * held,
        STAIRCASE_BYTES,
        f"{robots} robots (chunk_size x workspace.contacts x workspace.pairs) x {secs:.3g} s "
        f"({len(ws['levels'])} workspace.levels x workspace.hold), {held:.3g} samples held at a time "
        f"(a sample every {interval:g} s: workspace.sample_every x sim.dt)",
    )


def _get(cfg: Mapping, key: str):
    for part in key.split("."):
        cfg = cfg[part]
    return cfg


def _with(cfg: Mapping, key: str, value) -> dict:
    out = copy.deepcopy(dict(cfg))
    *path, last = key.split(".")
    node = out
    for part in path:
        node = node[part]
    node[last] = copy.deepcopy(value)
    return out


def over_limit(
    estimate: Callable[[Mapping], Cost],
    cfg: Mapping,
    defaults: Mapping,
    keys: Sequence[str],
    prefix: str = "config key",
) -> list[str]:
    """One message if the job `estimate(cfg)` is over a limit, else none. It names the key of
    `keys` whose default value (in `defaults`) would lower the estimate most, its value, the
    estimate and how it follows from the keys."""
    cost = estimate(cfg)
    if cost.burden() <= 1:
        return []
    lead, best = keys[0], cost.burden()
    for key in keys:
        b = estimate(_with(cfg, key, _get(defaults, key))).burden()
        if b < best:
            lead, best = key, b
    val = _get(cfg, lead)
    shown = (
        f"{len(val)} values"
        if isinstance(val, list) and len(val) > 6
        else f"{val:g}"
        if isinstance(val, float)
        else val
    )
    over = []
    if cost.memory > MEMORY_LIMIT:
        over.append(
            f"hold {_size(cost.memory)} of recorded samples ({cost.samples:.3g} robot-samples of "
            f"{_size(cost.sample_bytes)}), over the limit of {_size(MEMORY_LIMIT)} for one job"
        )
    if cost.steps > STEP_LIMIT:
        over.append(
            f"simulate {cost.steps:.3g} robot-steps ({cost.robot_seconds:.3g} robot-seconds in steps of "
            f"sim.dt = {cost.dt:g} s), over the limit of {STEP_LIMIT:.3g} for one job (about 10 h on one core)"
        )
    return [f"{prefix} {lead}: {shown} makes {cost.job} {' and '.join(over)}: {cost.detail}"]
