"""The state of a batch of robots and its geometry (docs/design.md §3): `State`, the rotations
of its quaternions, node positions and velocities, the CoG; and the initial states: at rest from
node positions (`from_nodes`) or standing on a face of a terrain (`stand_on`). `dynamics` moves
a state and offers these names too."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import frames
from . import topology as topo
from .params import Params
from .terrain import Terrain


@dataclass(frozen=True)
class State:
    """Batch of B robots. x, v: strut centres (m) and velocities (m/s), (B, 6, 3) world;
    q: unit quaternions (w, x, y, z) taking body to world components, (B, 6, 4), body axis 3
    along the strut; w: body angular velocities (rad/s), (B, 6, 3); anchor, stuck: friction
    stick points (B, 12, 3) m and flags (B, 12); t: time, s. With twisted-string actuators
    (`twisted`): motor_angle, motor_speed (B, 24) rad, rad/s at the output shaft, per cable
    (None for the pneumatic muscles; `dynamics.simulate` starts them at 0)."""

    x: np.ndarray
    v: np.ndarray
    q: np.ndarray
    w: np.ndarray
    anchor: np.ndarray
    stuck: np.ndarray
    t: float = 0.0
    motor_angle: np.ndarray | None = None
    motor_speed: np.ndarray | None = None

    _MOTORS = ("motor_angle", "motor_speed")

    def _motors(self, f) -> dict:
        """The motor fields mapped by f (none when they are None)."""
        return {k: f(getattr(self, k)) for k in self._MOTORS if getattr(self, k) is not None}

    @property
    def batch(self) -> int:
        return self.x.shape[0]

    def copy(self) -> State:
        return State(
            *(np.array(a, copy=True, order="C") for a in (self.x, self.v, self.q, self.w, self.anchor, self.stuck)),
            t=self.t,
            **self._motors(lambda a: np.array(a, copy=True, order="C")),
        )

    def check(self) -> None:
        for name in ("x", "v", "q", "w"):
            a = getattr(self, name)
            if np.isfinite(a).all():  # the usual case: one test per array
                continue
            bad = ~np.isfinite(a).reshape(a.shape[0], -1).all(axis=1)
            if bad.any():
                raise ValueError(f"state {name} is not finite for robot {int(np.argmax(bad))}")

    def take(self, idx: ArrayLike | slice) -> State:
        """The sub-batch of robots idx."""
        return State(
            *(a[idx] for a in (self.x, self.v, self.q, self.w, self.anchor, self.stuck)),
            t=self.t,
            **self._motors(lambda a: a[idx]),
        )

    @staticmethod
    def concat(states: Sequence[State], t: float | None = None) -> State:
        """One batch of the robots of `states`, in order, at time `t` s (default: the first's)."""
        return State(
            *(np.concatenate([getattr(s, k) for s in states]) for k in ("x", "v", "q", "w", "anchor", "stuck")),
            t=states[0].t if t is None else t,
            **{
                k: np.concatenate([getattr(s, k) for s in states])
                for k in State._MOTORS
                if all(getattr(s, k) is not None for s in states)
            },
        )


def axes(q: np.ndarray, column: int | None = None) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of quaternions (..., 4) (w, x, y, z; normalised here);
    columns are the body axes in world components. With `column` (0..2): that axis (..., 3)."""
    q = q / np.sqrt((q * q).sum(axis=-1))[..., None]
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    cols = (
        lambda: (1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)),
        lambda: (2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)),
        lambda: (2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)),
    )
    if column is not None:
        return np.stack(cols[column](), axis=-1)
    return np.stack([np.stack(c(), axis=-1) for c in cols], axis=-1)


def nodes(x: np.ndarray, q: np.ndarray, strut_length: float | np.ndarray) -> np.ndarray:
    """Node positions (..., 12, 3) m from strut centres x (..., 6, 3) and quaternions (..., 6, 4)
    (strut end = x + L c for the first node of a strut, x - L c for the second; eq. 4)."""
    half = 0.5 * np.asarray(strut_length, dtype=float)
    half = half.reshape(half.shape + (1,) * (x.ndim - half.ndim))[..., None, :] if half.ndim else half
    c = axes(q, 2) * (half if np.ndim(half) == 0 else half[..., 0, :][..., None, :])
    p = np.empty(x.shape[:-2] + (topo.N_NODES, 3))
    p[..., topo.STRUTS[:, 0], :] = x + c
    p[..., topo.STRUTS[:, 1], :] = x - c
    return p


def node_velocities(state: State, strut_length: float | np.ndarray) -> np.ndarray:
    """Node velocities (B, 12, 3) m/s."""
    half = 0.5 * np.asarray(strut_length, dtype=float).reshape(-1, 1, 1)
    R = axes(state.q)
    w = state.w
    cdot = R[..., :, 0] * w[..., 1:2] - R[..., :, 1] * w[..., 0:1]  # R (w x e3)
    u = np.empty(state.x.shape[:-2] + (topo.N_NODES, 3))
    u[..., topo.STRUTS[:, 0], :] = state.v + half * cdot
    u[..., topo.STRUTS[:, 1], :] = state.v - half * cdot
    return u


def cog(x: np.ndarray) -> np.ndarray:
    """Centre of gravity (..., 3) m: the mean of the strut centres (..., 6, 3) (equal masses)."""
    return x.mean(axis=-2)


def from_nodes(p: np.ndarray) -> State:
    """A state at rest from node positions (B, 12, 3) or (12, 3) m (strut lengths as given)."""
    p = np.asarray(p, dtype=float).reshape(-1, topo.N_NODES, 3)
    a, b = p[:, topo.STRUTS[:, 0]], p[:, topo.STRUTS[:, 1]]
    c = ((a - b) / np.linalg.norm(a - b, axis=-1, keepdims=True)).reshape(-1, 3)
    # the rotation taking e3 onto c about the axis e3 x c (quaternion w, x, y, z)
    half = 0.5 * np.arccos(np.clip(c[:, 2], -1.0, 1.0))
    ax = np.stack([-c[:, 1], c[:, 0], np.zeros(len(c))], axis=1)
    n = np.linalg.norm(ax, axis=1, keepdims=True)
    ax = np.where(n > 1e-12, ax / np.where(n > 1e-12, n, 1.0), [1.0, 0.0, 0.0])
    q = np.concatenate([np.cos(half)[:, None], np.sin(half)[:, None] * ax], axis=1)
    B = p.shape[0]
    z3 = np.zeros((B, topo.N_STRUTS, 3))
    return State(
        0.5 * (a + b),
        z3,
        q.reshape(B, topo.N_STRUTS, 4),
        z3.copy(),
        np.zeros((B, topo.N_NODES, 3)),
        np.zeros((B, topo.N_NODES), dtype=np.bool_),
    )


def stand_on(
    params: Params,
    face: int | Sequence[int],
    terrain: Terrain | None = None,
    batch: int = 1,
    position: ArrayLike = (0.0, 0.0),
    yaw_deg: float = 0.0,
) -> State:
    """The symmetric robot at rest with `face` (1..20 or three node numbers) on the terrain
    under `position` (m), turned by yaw_deg about the terrain normal. With no terrain (free
    mode) it is placed as if on flat ground at z = 0."""
    f = topo.face_number(face) - 1
    S = float(np.max(params.strut_length)) if np.ndim(params.strut_length) else params.strut_length
    r = float(np.max(params.strut_radius))
    p = topo.reference_nodes(S)
    tri = p[topo.FACES[f]]
    outward = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    outward *= np.sign(np.dot(outward, tri.mean(0)))  # the centre is at the origin
    outward /= np.linalg.norm(outward)
    terrain = terrain or Terrain.flat()
    px, py = map(float, position)
    if terrain.kind == "heightfield" and np.isnan(terrain.height(px, py)):
        raise ValueError(f"terrain has nothing under the robot at position {position}")
    up = terrain.normal_at(px, py) if terrain.kind != "none" else np.array([0.0, 0.0, 1.0])
    p = p @ (frames.turn(up, np.radians(yaw_deg)) @ frames.align(outward, -up)).T
    p[:, :2] += [px, py]
    if terrain.kind == "none":
        p[:, 2] += r - p[:, 2].min()
    else:
        h = terrain.height(p[:, 0], p[:, 1])
        if np.any(np.isnan(h)):
            raise ValueError(f"terrain has nothing under the robot at position {position}")
        p[:, 2] += np.max(h + r / terrain.normal_at(p[:, 0], p[:, 1])[:, 2] - p[:, 2])
    return from_nodes(np.repeat(p[None], batch, axis=0))
