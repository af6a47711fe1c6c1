"""Calibration against an independent simulator (issue 32, its second target): trajectories made
by MuJoCo, not by our kernel, calibrated by the package (`tensegrity.calibration.calibrate`, what
`tensegrity calibrate` runs), with the true values known.

The robot is the package's MJCF export (`tensegrity.bridges.mjcf`) with values drawn at random
from a named seed (stiffness, pretension, damping, gain 10-40 % off the defaults; a strut length
10-20 % off, its mass and muscle length scaled along; friction). Free mode: the export is the same
law and the same semi-implicit Euler as our kernel, to round-off, so a free calibration is exact
up to the noise. Grounded mode: MuJoCo's own soft contact (default solref and solimp, pyramidal
friction cones), not our penalty and stick spring (C1)-(C4), so a grounded calibration is a model
mismatch. The grounded robot settles 1 s on face (9,10,12), is excited by pressure steps for 2 s,
then pair #10 is ramped at 2 MPa/s until its CoG leaves the face's triangle (the experimenter
then holds the pressure at 1.1 times that level) and recorded 1.5 s longer: it rolls over edge
10-12. The roll (time of tipping, edge, face landed on) of MuJoCo's run is printed beside that of
our model with the true values, the model calibrated on all the samples and the one calibrated
on the samples before the ramp (the prediction check predicts the roll).

Each case is written as a motion-capture CSV in a frame turned and shifted from MuJoCo's world
(seeded; grounded: tilted 2-5 deg off level), read back, calibrated from the configured defaults
(the strut length, mass and muscle length known), and printed: true value, estimate, relative
error, 95 % interval, inside?, residual RMS (mm), prediction check (mm). Asserts nothing.

With --coverage N: N robots drawn from seeds chosen at random (from --seed), the free case with
noise (--noise mm) each, fitted with the initial state; printed: per robot which true values lie
inside their 95 % intervals, and the fraction inside, pooled and per parameter (the issue's target
on our own trajectories: 85-100 %).

MuJoCo (pip mujoco-core) is a test dependency pinned in environment.txt (MuJoCo never runs
inside the package: docs/design.md §8).
Usage: python benchmarks/bench_calibration_independent.py [--seed 32] [--seconds 4] [--noise 0.5]
       [--cases free,free-noisy,grounded,grounded-noisy] [--fit-contact] [--fit-friction] [--initial fit|data]
       [--residual positions|shape] [--keep DIR] [--tiny] [--coverage N]

--residual shape fits the grounded cases on the 24 cable lengths instead of the node positions
(`tensegrity calibrate --residual shape`); the free cases keep the positions. --fit-friction fits
our friction's stick spring and damper ((C3)-(C4)) with the four: MuJoCo's friction is a soft
constraint, more like a damper than a spring (docs/benchmarks.md).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from tensegrity import paper
from tensegrity.bridges.mjcf import controls, mjcf
from tensegrity.calibration import Measurement, calibrate
from tensegrity.calibration import model as mdl
from tensegrity.calibration import synthetic as syn
from tensegrity.io.formats.measured import read_measured, write_measured_csv
from tensegrity.physics import contact, frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import MAX_PRESSURE
from tensegrity.physics.state import nodes as node_positions
from tensegrity.physics.state import stand_on
from tensegrity.physics.terrain import Terrain

try:
    import mujoco
except ImportError:
    mujoco = None

DT = 1e-4  # s, both simulators
RATE = 100.0  # Hz, the measurement
FOUR = ("cable_stiffness", "cable_pretension", "cable_damping", "muscle_gain")
CONTACT = ("friction", "ground_stiffness", "ground_damping")  # fitted too, grounded, with --fit-contact
STICK = ("friction_stiffness", "friction_damping")  # fitted too, grounded, with --fit-friction
# (C2)-(C4)'s constants: MuJoCo's contact is solref/solimp, no true value
OURS_ONLY = ("ground_stiffness", "ground_damping", *STICK)
SETTLE = 1.0  # s: the grounded robot settles on MuJoCo's contact before the recording starts
ROLL_PAIR = 10  # pushes the robot over edge 10-12 of (9,10,12) (paper III.A)
ROUND_OFF = 1e-9  # relative: a noise-free fit's interval is round-off wide (~1e-13); the truth within this


def draw(seed: int) -> Params:
    """The true robot of `seed`: K, T0, B, Kg each 10-40 % above or below the defaults, strut
    length 10-20 % shorter or longer (mass and the muscle's minimum length scaled with it),
    friction 0.5-1.0."""
    rng = np.random.default_rng(seed)
    base = Params()

    def off(lo: float, hi: float) -> float:
        return float(1 + rng.choice([-1, 1]) * rng.uniform(lo, hi))

    s = off(0.1, 0.2)
    return base.replace(
        strut_length=base.strut_length * s,
        strut_mass=base.strut_mass * s,
        muscle_min_length=base.muscle_min_length * s,
        **{k: getattr(base, k) * off(0.1, 0.4) for k in FOUR},
        friction=float(rng.uniform(0.5, 1.0)),
    )


def excite_free(seconds: float, hold: float) -> np.ndarray:
    """Pair pressures (T, 12) MPa per sample over `seconds`: `synthetic.excitation`'s steps,
    pairs 1, 5, 10 at 2 MPa."""
    return steps_per_sample(syn.excitation(seconds, hold), hold, seconds)


def excite_grounded(seconds: float, hold: float) -> np.ndarray:
    """Pair pressures (T, 12) MPa per sample over `seconds`: steps of pairs 2, 5, 11 at 0.4 MPa
    (the robot rocks and stands). Tuned on seeds 0-5: at 0.8 MPa our model with the true values
    ends 6-75 mm RMS from MuJoCo after 2 s (its robots rock on MuJoCo's softer contact and
    drift), at 0.4 MPa 2-17 mm."""
    return steps_per_sample(syn.excitation(seconds, hold, pairs=(2, 5, 11), level=0.4), hold, seconds)


def steps_per_sample(steps: np.ndarray, hold: float, seconds: float) -> np.ndarray:
    """Pressure steps (K, 12) MPa each held `hold` s as pressures per sample (T, 12), T =
    seconds * RATE + 1 (sample k's pressure over the interval ending at it; sample 0's unused)."""
    per = int(round(hold * RATE))
    out = np.concatenate([np.zeros((1, topo.N_PAIRS)), np.repeat(steps, per, axis=0)])
    return out[: int(round(seconds * RATE)) + 1]


def margin(nodes: np.ndarray, face: int) -> np.ndarray:
    """Signed distance (..., ) m of the CoG's ground projection to the triangle of `face`'s
    nodes (their current x, y), positive inside: the robot tips when it turns negative."""
    tri = nodes[..., topo.FACES[face - 1], :2]
    return frames.margin_2d(nodes.mean(axis=-2)[..., :2], tri)


def run_mujoco(
    params: Params,
    mode: str,
    pressure: np.ndarray,
    settle: float = 0.0,
    roll: tuple[float, float, float, float] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's node positions (T, 12, 3) m (its world frame) at RATE Hz, and the pressures
    (T, 12) MPa applied, of the robot `params` started at rest on the paper's start face
    (`stand_on`; then `settle` s at zero pressure), driven by `pressure` (T0, 12) MPa (sample
    k's over the interval ending at it), time step DT. With roll = (rate MPa/s, cap, after s,
    longest s), the run goes on after `pressure` with pair ROLL_PAIR ramped at `rate` until the
    CoG leaves the start face's triangle (`margin`), then held at `cap` times its pressure then,
    for `after` s (the experimenter stops the ramp once the robot tips; at most `longest` s)."""
    grounded = mode == "grounded"
    prm = params if grounded else params.replace(gravity=0.0)
    start = topo.face_number(paper.START_FACE)
    state = stand_on(prm, start, Terrain.flat() if grounded else Terrain.none())
    model = mujoco.MjModel.from_xml_string(mjcf(prm, mode, DT, state))
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    if settle > 0:
        mujoco.mj_step(model, data, nstep=int(round(settle / DT)))
    every = int(round(1 / (RATE * DT)))

    def now() -> np.ndarray:
        qpos = data.qpos.reshape(topo.N_STRUTS, 7)
        return node_positions(qpos[:, :3], qpos[:, 3:], prm.strut_length)

    out, applied = [now()], [np.zeros(topo.N_PAIRS)]
    level, tipped, cap, k = 0.0, None, np.inf, 1
    while True:
        if k < len(pressure):
            p = pressure[k]
        elif roll is None or k * (1 / RATE) > roll[3] + 1e-9 or (tipped is not None and k > tipped + roll[2] * RATE):
            break
        else:
            level = min(level + roll[0] / RATE, MAX_PRESSURE, cap)
            p = np.zeros(topo.N_PAIRS)
            p[ROLL_PAIR - 1] = level
        data.ctrl[:] = controls(p)
        mujoco.mj_step(model, data, nstep=every)
        out.append(now())
        applied.append(p)
        if roll is not None and k >= len(pressure) and tipped is None and margin(out[-1], start) < 0:
            tipped, cap = k, roll[1] * level
        k += 1
    return np.array(out), np.array(applied)


def frame(rng: np.random.Generator, grounded: bool) -> tuple[np.ndarray, np.ndarray]:
    """A measurement frame (R (3, 3), offset (3,) m), measured = R^T (world - offset): free, any
    rotation; grounded, a yaw and a tilt of 2-5 deg off level; offset within 1 m."""
    yaw = frames.turn([0.0, 0.0, 1.0], rng.uniform(0, 2 * np.pi))
    if grounded:
        a = rng.uniform(0, 2 * np.pi)
        R = yaw @ frames.turn([np.cos(a), np.sin(a), 0.0], np.radians(rng.uniform(2, 5)))
    else:
        axis = rng.normal(size=3)
        R = yaw @ frames.turn(axis / np.linalg.norm(axis), rng.uniform(0, np.pi))
    return R, rng.uniform(-1, 1, 3)


def roll_of(nodes: np.ndarray, radius: float, after: int) -> tuple[float, str, int]:
    """The roll in node positions (T, 12, 3) m (world, ground z = 0, RATE Hz): the time (s) the
    CoG first leaves the start face's triangle from sample `after` on (NaN: never), the edge it
    crosses ('10-12'), the face resting on the ground at the last sample (0: none)."""
    start = topo.face_number(paper.START_FACE)
    out = np.flatnonzero(margin(nodes[after:], start) < 0)
    gap = contact.clearance(nodes[-1], Terrain.flat(), 0.0) - radius
    face = int(contact.resting_face(gap, radius))
    if not out.size:
        return float("nan"), "-", face
    k = after + int(out[0])
    tri = nodes[k, topo.FACES[start - 1], :2]
    e = frames.crossed_edge(nodes[k].mean(axis=0)[:2], tri)
    return k / RATE, "-".join(map(str, topo.edge_nodes(start, e))) if e is not None else "?", face


CASES = {  # name: (mode, noise on)
    "free": ("free", False),
    "free-noisy": ("free", True),
    "grounded": ("grounded", False),
    "grounded-noisy": ("grounded", True),
}


def measured_case(a: argparse.Namespace, truth: Params, name: str, folder: Path):
    """MuJoCo's run of case `name` written as a motion-capture CSV in a turned and shifted frame
    (with noise if the case has it) and read back: (measurement, world nodes (T, 12, 3) m, the
    sample where the roll's ramp starts (grounded; else None))."""
    mode, noisy = CASES[name]
    rng = np.random.default_rng([a.seed, list(CASES).index(name)])
    if mode == "free":
        world, pressure = run_mujoco(truth, mode, excite_free(a.seconds, a.hold))
        ramp = None
    else:
        excite = excite_grounded(a.excite, a.hold)
        roll = None if a.tiny else (a.ramp, 1.1, 1.5, 8.0)
        world, pressure = run_mujoco(truth, mode, excite, SETTLE, roll)
        ramp = len(excite) if roll else None
    R, offset = frame(rng, mode == "grounded")
    nodes = (world - offset) @ R
    if noisy:
        nodes = nodes + rng.normal(0.0, a.noise * 1e-3, nodes.shape)
    t = np.arange(len(pressure)) / RATE
    path = write_measured_csv(Measurement(t, nodes, pressure, "", f"MuJoCo {name}"), folder / f"{name}.csv")
    return read_measured(path), world, ramp


def report(truth: Params, c, wall: float) -> None:
    """The table of one case. inside: the true value in the 95 % interval ('yes'), or not but
    within ROUND_OFF of it ('round-off': a noise-free fit's interval is round-off wide), 'NO', or
    'none' (no interval given, named below)."""
    print(f"{'parameter':<18} {'true':>10} {'estimate':>11} {'rel. error':>10} {'95 % interval':>26} {'inside':>9}")
    for k, e, lo, hi in zip(c.names, c.estimate, c.unc.lower, c.unc.upper, strict=True):
        if k in OURS_ONLY:  # no true value: MuJoCo's contact has no such constant
            print(f"{k:<18} {'n/a':>10} {e:>11.6g} {'':>10} {f'[{lo:.6g}, {hi:.6g}]':>26} {'n/a':>9}")
            continue
        tv = float(getattr(truth, k))
        tol = ROUND_OFF * abs(tv)
        inside = "yes" if lo <= tv <= hi else "round-off" if lo - tol <= tv <= hi + tol else "NO"
        inside = "none" if np.isnan(lo) else inside
        print(f"{k:<18} {tv:>10.5g} {e:>11.6g} {e / tv - 1:>10.2e} {f'[{lo:.6g}, {hi:.6g}]':>26} {inside:>9}")
    line = f"residual RMS {c.rms_mm:.3g} mm"
    if c.prediction:
        p = c.prediction
        line += (
            f"; prediction check: fitted up to {p['fit_until']:.2f} s (RMS {p['rms_fit_mm']:.3g} mm), "
            f"predicted the rest (RMS {p['rms_predict_mm']:.3g} mm)"
        )
    print(f"{line}; {wall:.0f} s wall, {c.nfev} evaluations")
    if c.prediction:
        pairs = zip(c.names, c.prediction["estimate"], strict=True)
        errs = [f"{k} {e / float(getattr(truth, k)) - 1:+.2e}" for k, e in pairs if k not in OURS_ONLY]
        print(f"fitted up to {c.prediction['fit_until']:.2f} s only, relative errors: {', '.join(errs)}")
    if c.unc.undetermined:
        print(f"not determined: {'; '.join(c.unc.undetermined)}")


def true_model(m: Measurement, truth: Params, mode: str) -> tuple[np.ndarray, float, float]:
    """Our model with the true values, the initial state and frame from the data (no fit): its
    nodes (T, 12, 3) m (world) and the RMS (mm) of its node coordinates and of its cable lengths
    from the measured ones: the model mismatch."""
    prob = mdl.problem(m, truth, FOUR[:1], mode, DT, False, False)
    sim = prob.simulate(prob.x0[None])[0]
    shape = mdl.lengths(sim) - mdl.lengths(m.nodes)
    rms = [float(np.sqrt(np.nanmean(e**2)) * 1e3) for e in (sim - prob.measured(prob.x0), shape)]
    return sim, *rms


def roll_table(truth: Params, world: np.ndarray, c, ramp: int, true_nodes: np.ndarray) -> None:
    """The roll of MuJoCo's run against our model's with the true values, the calibrated model's
    (fitted on all the samples) and the model fitted before the ramp (the prediction check),
    all from sample `ramp` on."""
    r = float(truth.strut_radius)
    rows = [("MuJoCo (measured)", world), ("true values in our model", true_nodes)]
    rows.append(("calibrated on all samples", c.simulated))
    if c.prediction:
        rows.append((f"calibrated up to {c.prediction['fit_until']:.2f} s", c.prediction["simulated"]))
    print(f"{'roll':<28} {'tips at':>9} {'over edge':>10} {'lands on':>10}")
    for label, nodes in rows:
        t, edge, face = roll_of(nodes, r, ramp)
        print(f"{label:<28} {t:>8.2f}s {edge:>10} {topo.face_label(face) if face else 'none':>10}")


def coverage(a: argparse.Namespace, n: int, folder: Path) -> None:
    """The coverage of the 95 % intervals on n free MuJoCo robots with noise (module docstring)."""
    seeds = np.random.default_rng(a.seed).integers(1000, 10**6, n)
    print(f"\ncoverage: {n} robots (seeds {', '.join(map(str, seeds))}), free, noise {a.noise:g} mm, {a.seconds:g} s")
    print(f"{'seed':>7} " + " ".join(f"{k[:14]:>14}" for k in FOUR) + f" {'RMS mm':>7} {'s/noise':>8} {'CPU s':>6}")
    inside = []
    for seed in seeds:
        truth = draw(int(seed))
        start = Params().replace(**{k: getattr(truth, k) for k in ("strut_length", "strut_mass", "muscle_min_length")})
        b = argparse.Namespace(**{**vars(a), "seed": int(seed)})
        m, _, _ = measured_case(b, truth, "free-noisy", folder)
        c0 = time.process_time()
        c = calibrate(m, start, FOUR, "free", DT, a.initial == "fit", check=0.0)
        true = np.array([getattr(truth, k) for k in FOUR])
        ok = (c.unc.lower <= true) & (true <= c.unc.upper)
        inside.append(ok)
        z = (c.estimate - true) / c.unc.se
        cells = " ".join(f"{('in' if o else 'OUT') + f' {e:+.2f} se':>14}" for o, e in zip(ok, z, strict=True))
        print(f"{seed:>7} {cells} {c.rms_mm:>7.3f} {c.unc.s / (a.noise * 1e-3):>8.3f} {time.process_time() - c0:>6.0f}")
    inside = np.array(inside)
    per = ", ".join(f"{k} {v:.2f}" for k, v in zip(FOUR, inside.mean(axis=0), strict=True))
    print(f"coverage: {inside.mean():.3f} of {inside.size} true values inside their 95 % intervals ({per})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=32, help="named seed of the true robot, frames and noise")
    ap.add_argument("--seconds", type=float, default=4.0, help="free trajectories, s (at most 8)")
    ap.add_argument("--hold", type=float, default=0.5, help="each pressure step, s")
    ap.add_argument("--excite", type=float, default=2.0, help="grounded: steps before the roll's ramp, s")
    ap.add_argument("--ramp", type=float, default=2.0, help="grounded: ramp of pair #10, MPa/s")
    ap.add_argument("--noise", type=float, default=0.5, help="Gaussian noise on every coordinate, mm")
    ap.add_argument("--cases", default=",".join(CASES), help=f"comma-separated, of {', '.join(CASES)}")
    ap.add_argument("--fit-contact", action="store_true", help=f"grounded: fit {', '.join(CONTACT)} too")
    ap.add_argument("--fit-friction", action="store_true", help=f"grounded: fit {', '.join(STICK)} too")
    ap.add_argument("--initial", choices=["fit", "data"], default="fit", help="initial state fitted or from the data")
    ap.add_argument("--residual", choices=["positions", "shape"], default="positions", help="grounded cases' residual")
    ap.add_argument("--coverage", type=int, default=0, help="then the coverage over this many robots (free, noisy)")
    ap.add_argument("--keep", type=Path, help="folder to keep the measured CSV files in")
    ap.add_argument(
        "--tiny",
        action="store_true",
        help="a smoke run: 0.3 s, no roll, no check, --initial data; grounded: the stiffness only, the rest true",
    )
    a = ap.parse_args()
    cases = ["free", "grounded"] if a.tiny else [c.strip() for c in a.cases.split(",") if c.strip()]
    bad = [c for c in cases if c not in CASES]
    if bad:
        ap.error(f"argument --cases: {', '.join(bad)} not of {', '.join(CASES)}")
    if a.tiny:
        a.seconds, a.hold, a.excite, a.initial = 0.3, 0.1, 0.3, "data"
    if not 0 < a.seconds <= 8 or not 0 < a.excite <= 6:
        ap.error("argument --seconds or --excite: out of (0, 8] s or (0, 6] s")
    if mujoco is None:
        sys.exit(
            "bench_calibration_independent.py: MuJoCo is not installed: "
            "pip install -r benchmarks/requirements-mujoco.txt"
        )
    truth = draw(a.seed)
    start = Params().replace(**{k: getattr(truth, k) for k in ("strut_length", "strut_mass", "muscle_min_length")})
    known = ", ".join(f"{k} {getattr(truth, k):.4g}" for k in ("strut_length", "strut_mass", "muscle_min_length"))
    print(
        f"MuJoCo {mujoco.__version__}, seed {a.seed}: the true robot has {known} (known to the fit), friction "
        f"{truth.friction:.3g}; the fit starts from the configured defaults; dt {DT:g} s, {RATE:g} Hz"
    )
    calibrate(syn.measure(start, syn.excitation(0.03, 0.01), 0.01), start, FOUR[:1], "free", DT, False, check=0.0)
    with tempfile.TemporaryDirectory() as tmp:
        folder = a.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        for name in cases:
            m, world, ramp = measured_case(a, truth, name, folder)
            mode = CASES[name][0]
            fit = FOUR + (CONTACT if a.fit_contact and mode == "grounded" else ())
            fit += STICK if a.fit_friction and mode == "grounded" else ()
            begin = start
            if a.tiny and mode == "grounded":  # a smoke run of the grounded path, cheaply: one parameter off
                fit, begin = fit[:1], truth.replace(cable_stiffness=start.cable_stiffness)
            check = 1 - (ramp + 1) / m.t.size if ramp else (0.0 if a.tiny else 0.25)
            print(
                f"\n{name}: {m.t.size} samples ({m.t[-1]:.2f} s) of {Path(m.source).name}, noise "
                f"{a.noise if CASES[name][1] else 0:g} mm, fitting {', '.join(fit)}"
                + (f" to the {a.residual}" if mode == "grounded" else "")
            )
            t0 = time.perf_counter()
            residual = a.residual if mode == "grounded" else "positions"
            c = calibrate(m, begin, fit, mode, DT, a.initial == "fit", check=check, residual=residual)
            report(truth, c, time.perf_counter() - t0)
            if mode == "grounded":
                sim, rms, rms_shape = true_model(m, truth, mode)
                print(
                    f"our model with the true values (initial state and frame from the data): RMS {rms:.3g} mm, "
                    f"of the cable lengths {rms_shape:.3g} mm"
                )
                if ramp:
                    roll_table(truth, world, c, ramp, sim)
        if a.coverage > 0:
            coverage(a, a.coverage, folder)


if __name__ == "__main__":
    main()
