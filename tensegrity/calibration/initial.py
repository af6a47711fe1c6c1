"""The initial state of a measured robot and the frame of its measurement (docs/design.md §9).

Pose: each strut is a rigid segment fitted to its two measured ends (the least-squares fit of a
segment to two points: centre at their midpoint, axis along their difference; a measured length
other than S is absorbed, the error is half the length difference at each end). The spin of a
strut about its own axis moves no node and is set to zero.
Velocities: the node velocities of the first samples by the one-sided second-order difference
(-3 p0 + 4 p1 - p2) / (2 h) (error h^2 p'''/3), or the first difference (p1 - p0) / h (error
h p''/2) if the second sample after the first is not on the grid; the fit refines them
(`model`: the initial state is fitted with the parameters, `INITIAL_NAMES`).
Frame: world = R (measured) + o. In the grounded mode the three lowest nodes of the first sample
(measured z roughly up) give the first guess: the plane through them is turned level and put at
z = r (the robot rests on them); the fit refines its tilt and height (`FRAME_NAMES`). Yaw and
horizontal offset leave a flat ground unchanged and are not fitted; in the free mode no part of
the frame can be seen (the motion is the same in any frame) and the identity is kept.
"""

from __future__ import annotations

import numpy as np

from ..physics import frames
from ..physics import topology as topo
from ..physics.state import State, axes, from_nodes

__all__ = ["INITIAL_NAMES", "FRAME_NAMES", "node_velocities", "state_from", "perturbed", "level_frame", "tilted"]

# per strut k = 1..6: centre (m), tilt of its axis about body x, y (rad), velocity (m/s), body
# angular velocity about x, y (rad/s)
INITIAL_NAMES = tuple(
    f"strut{k}_{q}"
    for k in range(1, topo.N_STRUTS + 1)
    for q in ("x", "y", "z", "tilt_a", "tilt_b", "vx", "vy", "vz", "wa", "wb")
)
# the frame's tilt about world x, y (rad) about the robot's first centroid, and its height (m)
FRAME_NAMES = ("frame_tilt_x", "frame_tilt_y", "frame_z")


def node_velocities(nodes: np.ndarray, index: np.ndarray, h: float) -> np.ndarray:
    """Node velocities (12, 3) m/s at the first sample from nodes (T, 12, 3) m on grid `index`
    (sampling interval h s); zero where a sample it needs is missing or NaN."""
    if index.size > 2 and index[1] == 1 and index[2] == 2 and np.isfinite(nodes[1:3]).all():
        return (-3 * nodes[0] + 4 * nodes[1] - nodes[2]) / (2 * h)
    if index[1] == 1 and np.isfinite(nodes[1]).all():
        return (nodes[1] - nodes[0]) / h
    return np.zeros_like(nodes[0])


def state_from(p: np.ndarray, u: np.ndarray) -> State:
    """A state (batch 1) from node positions p (12, 3) m and velocities u (12, 3) m/s: each strut
    fitted as a rigid segment (module docstring), v the mean of its ends' velocities, the body
    angular velocity from their difference (its component along the strut dropped)."""
    s = from_nodes(p)
    a, b = p[topo.STRUTS[:, 0]], p[topo.STRUTS[:, 1]]
    ua, ub = u[topo.STRUTS[:, 0]], u[topo.STRUTS[:, 1]]
    c = (a - b) / np.linalg.norm(a - b, axis=-1, keepdims=True)
    cdot = (ua - ub) / np.linalg.norm(a - b, axis=-1, keepdims=True)
    w_world = np.cross(c, cdot)  # the rotation rate of the axis c, perpendicular to it
    w_body = np.einsum("kji,kj->ki", axes(s.q[0]), w_world)
    w_body[:, 2] = 0.0
    return State(s.x, 0.5 * (ua + ub)[None], s.q, w_body[None], s.anchor, s.stuck)


def _quat_mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product of quaternions (..., 4) (w, x, y, z)."""
    w1, x1, y1, z1 = np.moveaxis(p, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ],
        axis=-1,
    )


def perturbed(s: State, d: np.ndarray) -> State:
    """A batch of states from one state s (batch 1) and changes d (B, 60) in the order of
    INITIAL_NAMES: centres + d, axes turned by the body rotation vector (a, b, 0), velocities and
    body angular velocities (about x, y) set to s's + d."""
    d = np.asarray(d, float).reshape(-1, topo.N_STRUTS, 10)
    B = d.shape[0]
    rot = np.concatenate([d[..., 3:5], np.zeros((B, topo.N_STRUTS, 1))], axis=-1)
    ang = np.linalg.norm(rot, axis=-1, keepdims=True)
    axis = np.divide(rot, ang, out=np.zeros_like(rot), where=ang > 0)
    dq = np.concatenate([np.cos(ang / 2), np.sin(ang / 2) * axis], axis=-1)
    w = np.repeat(s.w, B, axis=0)
    w[..., :2] += d[..., 8:10]
    return State(
        s.x + d[..., 0:3],
        s.v + d[..., 5:8],
        _quat_mul(np.repeat(s.q, B, axis=0), dq),
        w,
        np.zeros((B, topo.N_NODES, 3)),
        np.zeros((B, topo.N_NODES), dtype=np.bool_),
    )


def level_frame(p: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """The first guess of the frame (R (3, 3), o (3,) m) of a robot resting on the ground, from
    its first node positions p (12, 3) m (measured z roughly up): the plane through the three
    lowest nodes turned level (normal to +z) and put at z = radius m."""
    low = p[np.argsort(p[:, 2])[:3]]
    n = np.cross(low[1] - low[0], low[2] - low[0])
    n *= np.sign(n[2]) if n[2] != 0 else 1.0
    R = frames.align(n / np.linalg.norm(n), np.array([0.0, 0.0, 1.0]))
    o = np.array([0.0, 0.0, radius - (low @ R.T)[:, 2].mean()])
    return R, o


def tilted(R: np.ndarray, o: np.ndarray, centre: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The frame (R, o) changed by d = (tilt_x, tilt_y, z) (`FRAME_NAMES`): turned by the world
    rotation vector (tilt_x, tilt_y, 0) rad about the world point `centre` (3,) m, raised z m."""
    a = np.array([d[0], d[1], 0.0])
    ang = float(np.linalg.norm(a))
    T = frames.turn(a / ang, ang) if ang > 0 else np.eye(3)
    return T @ R, T @ (o - centre) + centre + np.array([0.0, 0.0, d[2]])
