"""The robot as a MuJoCo model (MJCF text; issue 33, item 1), for any `Params`.

Six rigid struts on free joints (`strut1`..`strut6` in topology.STRUTS order) with the masses and
thin-tube inertias of docs/design.md §3 (I_t = m (S^2/12 + r^2/4), I_a = m r^2/2 about the strut
axis, body axis 3), a site at each of the 12 nodes (`node1`..`node12`: strut end x +- (S/2) c),
and per cable A-B (24, smaller node first) a spatial tendon and a `general` actuator, both named
`cable_A_B`, whose control is its pair's pressure P (MPa). The actuator force is eq. 1-2 with
a = 1, written in MuJoCo's affine terms

    force = gain ctrl + bias,  gain = Kg Lmin - Kg l,  bias = K L - K l - B dl/dt,

i.e. force = -(K (l - L) + B dl/dt + Kg P (l - Lmin)), clamped by forcerange to [-1e10, 0] N:
the tension of eq. 2, the whole sum clamped so that a cable never pushes (MuJoCo's positive
actuator force lengthens a tendon). Semi-implicit Euler (`integrator="Euler"`, implicit damping
off: `eulerdamp="disable"`) with the time step dt, the scheme of `physics/kernel`.

Where it is not exact (the approximations and their errors):
- The inner clamp of eq. 1, max(0, l - Lmin), is not affine: MuJoCo's muscle term is
  Kg P (l - Lmin) also for l < Lmin. Both laws give the same tension unless l < Lmin and
  K (l - L) + B dl/dt > 0, which needs a cable shorter than Lmin lengthening faster than
  K (L - Lmin) / B (43 m/s at the defaults, `exact_below`); there the export's tension is lower
  by Kg P (Lmin - l). Runs that stay below that rate (every run of the toolkit so far: the
  kernel stops a run at 50 m/s strut end speed) are the same law.
- a != 1 (eq. 2's exponent) and a strut damping ds != 0 (eq. 3; MuJoCo's free joint has one
  damping for its six degrees of freedom, the law needs m ds and I ds) cannot be written: a
  ValueError names the parameter.
- Grounded mode: gravity, a plane z = 0 and a sphere of radius r at each node with friction mu,
  touching the plane only (struts do not collide with each other, as in the kernel). MuJoCo's
  contact is its own soft constraint (default solref, solimp; pyramidal friction cones), not
  the penalty and stick spring of (C1)-(C4): grounded runs differ (benchmarks/bench_mujoco.py
  reports by how much). Only flat ground is exported.
- Only the actuator law of eq. 1-2 (`LAW`, its fields in `physics.actuator`); another law is
  refused (NotImplementedError) until it is written here.
- Control bounds 0..schedule.MAX_PRESSURE MPa (ctrlrange): MuJoCo clamps a control outside,
  where the toolkit raises.

The bodies start at `state` (default: the robot at rest on the paper's start face (9,10,12),
`state.stand_on`), which is the model's qpos0 (mj_resetData puts it there).
"""

from __future__ import annotations

import numpy as np

from .. import paper
from ..physics import actuator
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import MAX_PRESSURE
from ..physics.state import State, stand_on
from ..physics.terrain import Terrain

MODES = ("free", "grounded")
# the fields of the one actuator law this export writes (eq. 1-2); a law with other fields
# (issue 31, the prototype's motor-driven actuator) is refused by name until it is written here
LAW = ("cable_exponent", "cable_stiffness", "cable_rest_length", "cable_damping", "muscle_min_length", "muscle_gain")
INTEGRATORS = ("Euler", "implicitfast", "RK4")  # MuJoCo's; only Euler is the kernel's scheme
FORCE_LIMIT = 1e10  # N: the largest tension the actuator may give (the clamp at 0 is exact)


def cable_name(cable: int) -> str:
    """`cable_A_B` of cable index (0..23, topology.CABLES order), nodes 1-based, smaller first."""
    a, b = sorted(int(n) + 1 for n in topo.CABLES[cable])
    return f"cable_{a}_{b}"


def _scalar(params: Params, name: str) -> float:
    v = np.asarray(getattr(params, name), dtype=float)
    if v.ndim:
        raise ValueError(f"the MuJoCo export needs one robot: parameter {name} is an array of shape {v.shape}")
    return float(v)


def exact_below(params: Params) -> float:
    """The cable-length rate K (L - Lmin) / B (m/s) below which the exported law equals eq. 1-2
    exactly (module docstring); inf without damping."""
    K, L, B = (_scalar(params, k) for k in ("cable_stiffness", "cable_rest_length", "cable_damping"))
    return float("inf") if B == 0 else K * (L - _scalar(params, "muscle_min_length")) / B


def check(params: Params, mode: str, dt: float, integrator: str = "Euler") -> None:
    """ValueError naming the first value the export cannot write (module docstring)."""
    if mode not in MODES:
        raise ValueError(f"mode {mode!r} is not one of {MODES}")
    if tuple(actuator.NAMES) != LAW:
        raise NotImplementedError(
            f"the actuator law's fields {actuator.NAMES} are not eq. 1-2's {LAW}: the MuJoCo export "
            "cannot write this actuator yet"
        )
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator {integrator!r} is not one of {INTEGRATORS}")
    if not (np.isfinite(dt) and 0 < dt <= 1e-3):
        raise ValueError(f"time step dt = {dt!r} s must be in (0, 1e-3]")
    for name in ("strut_length", "strut_radius", "strut_mass", "gravity", "friction"):
        _scalar(params, name)
    if _scalar(params, "cable_exponent") != 1.0:
        raise ValueError(
            f"parameter cable_exponent = {params.cable_exponent!r}: the MuJoCo export writes eq. 2 for a = 1 only "
            "(MuJoCo's actuator gain and bias are affine in the tendon length)"
        )
    if _scalar(params, "strut_damping") != 0.0:
        raise ValueError(
            f"parameter strut_damping = {params.strut_damping!r}: MuJoCo's free joint has one damping for its "
            "six degrees of freedom, eq. 3 needs m ds and I ds; export with params.strut_damping=0"
        )


def mjcf(
    params: Params,
    mode: str = "free",
    dt: float = 1e-4,
    state: State | None = None,
    integrator: str = "Euler",
    order: np.ndarray | None = None,
) -> str:
    """MJCF text (module docstring) of the robot with scalar `params` in `mode` (free: no
    gravity, no contact; grounded: gravity, the plane z = 0, friction), time step dt (s), the
    bodies at `state` (batch 1; default at rest on the paper's start face), MuJoCo's
    `integrator`, tendons and actuators in the cable order `order` (24,) (default CABLES')."""
    check(params, mode, dt, integrator)
    grounded = mode == "grounded"
    if state is None:
        state = stand_on(params, paper.START_FACE, Terrain.flat() if grounded else Terrain.none())
    if state.batch != 1:
        raise ValueError(f"the MuJoCo export needs one robot: the state has {state.batch}")
    S, r, m = (_scalar(params, k) for k in ("strut_length", "strut_radius", "strut_mass"))
    It, Ia = m * (S * S / 12 + r * r / 4), m * r * r / 2  # thin tube, kg m^2 (§3)
    K, L, B = (_scalar(params, k) for k in ("cable_stiffness", "cable_rest_length", "cable_damping"))
    Kg, Lmin, mu = (_scalar(params, k) for k in ("muscle_gain", "muscle_min_length", "friction"))
    g = _scalar(params, "gravity") if grounded else 0.0
    contact = "" if grounded else ' contact="disable"'
    f = lambda v: repr(float(v))  # the shortest text that reads back to the same double
    out = [
        '<mujoco model="tensegrity">',
        "  <!-- written by tensegrity.bridges.mjcf: eq. 1-2 as affine actuators, see its docstring; exact for",
        f"       cable-length rates below {exact_below(params):.4g} m/s; grounded contact is MuJoCo's own -->",
        f'  <option timestep="{f(dt)}" integrator="{integrator}" gravity="0 0 {f(-g)}">',
        f'    <flag eulerdamp="disable"{contact}/>',
        "  </option>",
        "  <worldbody>",
    ]
    if grounded:
        out.append(
            f'    <geom name="ground" type="plane" size="0 0 1" contype="0" conaffinity="1" friction="{f(mu)} 0 0"/>'
        )
    for i, (a, b) in enumerate(topo.STRUTS):
        x, q = state.x[0, i], state.q[0, i] / np.linalg.norm(state.q[0, i])
        out.append(
            f'    <body name="strut{i + 1}" pos="{" ".join(map(f, x))}" quat="{" ".join(map(f, q))}"><freejoint/>'
        )
        out.append(f'      <inertial pos="0 0 0" mass="{f(m)}" diaginertia="{f(It)} {f(It)} {f(Ia)}"/>')
        for n, z in ((a, S / 2), (b, -S / 2)):  # first node at +S/2 on body axis 3 (eq. 4)
            out.append(f'      <site name="node{n + 1}" pos="0 0 {f(z)}" size="{f(r)}"/>')
            if grounded:  # a contact sphere touching the plane only (contype 1 & plane's conaffinity 1)
                out.append(
                    f'      <geom type="sphere" size="{f(r)}" pos="0 0 {f(z)}" contype="1" conaffinity="0" '
                    f'friction="{f(mu)} 0 0"/>'
                )
        out.append("    </body>")
    out += ["  </worldbody>", "  <tendon>"]
    cables = np.arange(topo.N_CABLES) if order is None else np.asarray(order)
    for j in cables:
        a, b = topo.CABLES[j]
        out.append(
            f'    <spatial name="{cable_name(j)}"><site site="node{a + 1}"/><site site="node{b + 1}"/></spatial>'
        )
    out += ["  </tendon>", "  <actuator>"]
    for j in cables:
        # force = gain ctrl + bias = -(Kg P (l - Lmin) + K (l - L) + B dl/dt), clamped to <= 0
        out.append(
            f'    <general name="{cable_name(j)}" tendon="{cable_name(j)}" gaintype="affine" '
            f'gainprm="{f(Kg * Lmin)} {f(-Kg)} 0" biastype="affine" biasprm="{f(K * L)} {f(-K)} {f(-B)}" '
            f'forcelimited="true" forcerange="{f(-FORCE_LIMIT)} 0" ctrllimited="true" ctrlrange="0 {f(MAX_PRESSURE)}"/>'
        )
    out += ["  </actuator>", "</mujoco>", ""]
    return "\n".join(out)


def controls(pressure: np.ndarray, order: np.ndarray | None = None) -> np.ndarray:
    """Actuator controls (..., 24) MPa of pair pressures (..., 12) MPa (each cable its pair's) or
    of cable pressures (..., 24) (`topology.cable_levels`), in the actuator order of `mjcf`
    (`order`, default topology.CABLES')."""
    cables = np.arange(topo.N_CABLES) if order is None else np.asarray(order)
    return topo.cable_levels(pressure)[..., cables]
