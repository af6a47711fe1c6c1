"""The slope ground of the gravity-aware workspace and the robot's placement on it (issue 10,
item 2). The ground is a height field of planar strips, one per slope, each rising toward +x
(`slope_field`); the robot is turned about the strip's normal so that the slope's heading, the
uphill direction in the contact face's support frame (deg from the frame's x axis toward y;
docs/design.md §2), is the one asked for (`place`, `heading_of`). `gravity_frame`: the CoG
projected along gravity onto the plane of the deformed contact face and its margin (paper
Fig. 10). `stands`: whether the unactuated robot stays on its face there (direct simulation).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import frames
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import Schedule
from ..physics.terrain import Terrain
from ..physics.twisted import TwistedString, Voltages

STRIP = 2.5  # m, width of one slope strip of the test ground
HALF_LENGTH = 2.0  # m, the strips run from x = -HALF_LENGTH to +HALF_LENGTH
SPACING = 0.25  # m, height-field cell


def slope_field(slopes: ArrayLike) -> tuple[Terrain, np.ndarray]:
    """Ground with one planar strip per slope (deg, rising toward +x), STRIP m wide; returns the
    terrain and the strip centres (S, 2) m."""
    slopes = np.atleast_1d(np.asarray(slopes, float))
    if np.any(~np.isfinite(slopes)) or np.any(np.abs(slopes) >= 60):
        raise ValueError(f"slopes {slopes.tolist()} deg must be finite and within (-60, 60)")
    x = np.arange(-HALF_LENGTH, HALF_LENGTH + 1e-9, SPACING)
    y = np.arange(-STRIP / 2, STRIP * (slopes.size - 0.5) + 1e-9, SPACING)
    strip = np.clip(np.floor(y / STRIP + 0.5).astype(int), 0, slopes.size - 1)
    heights = np.tan(np.radians(slopes[strip]))[None, :] * x[:, None]
    centres = np.stack([np.zeros(slopes.size), STRIP * np.arange(slopes.size)], axis=1)
    return Terrain(kind="heightfield", origin=(x[0], y[0]), spacing=SPACING, heights=heights), centres


def gravity_frame(nodes: np.ndarray, face: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For node positions (..., 12, 3) m on `face`: cog (..., 3) m and support (..., 3, 3) m in
    the deformed face's support frame, the CoG projected along gravity onto the face plane
    (..., 2) m and its signed margin (...,) m (paper Fig. 10, `frames.margin_2d`)."""
    origin, rot = frames.face_frame(nodes, face)
    cog, support = frames.in_support_frame(nodes, face, (origin, rot))
    g = np.einsum("...ij,j->...i", rot, ct.GRAVITY_DIR)  # gravity in the support frame
    proj = ct.project_along_gravity(cog, np.zeros(3), np.eye(3)[2], g)[..., :2]  # onto z = 0
    return cog, support, proj, frames.margin_2d(proj, support[..., :2])


def heading_of(nodes: np.ndarray, face: int, uphill: ArrayLike = (1.0, 0.0, 0.0)) -> np.ndarray:
    """Heading (...,) deg of the world direction `uphill` in the support frame of `face` on
    node positions (..., 12, 3) m."""
    _, rot = frames.face_frame(nodes, face)
    u = np.einsum("...ij,j->...i", rot, np.asarray(uphill, float))
    return np.degrees(np.arctan2(u[..., 1], u[..., 0]))


def place(params: Params, face: int, terrain: Terrain, position: ArrayLike, heading: float, batch: int = 1) -> d.State:
    """`batch` symmetric robots at rest on `face` at `position` (m) of a terrain rising toward
    +x, turned so that the uphill direction has `heading` deg in the face's support frame."""
    s0 = d.stand_on(params, face, terrain, position=position)
    h0 = float(heading_of(d.nodes(s0.x, s0.q, params.strut_length)[0], face))
    return d.stand_on(params, face, terrain, batch, position=position, yaw_deg=h0 - heading)


def stands(
    params: Params,
    faces: Sequence[int],
    slopes: ArrayLike,
    headings: ArrayLike,
    settle: float = 1.0,
    dt: float = 1e-4,
    motors: TwistedString | None = None,
) -> np.ndarray:
    """Direct simulation: does the unactuated robot b, placed on faces[b] on a slope of
    slopes[b] deg at headings[b] deg, still stand on it after `settle` s? (B,) bool. With
    `motors`, the twisted-string robot at 0 V."""
    terrain, centres = slope_field(slopes)
    state = d.State.concat(
        [place(params, int(f), terrain, centres[b], h) for b, (f, h) in enumerate(zip(faces, headings))]
    )
    n = int(round(settle / dt))
    sched = (Schedule if motors is None else Voltages).constant(np.zeros(topo.N_PAIRS), settle)
    _, tr = d.simulate(params, state, sched, terrain, dt, n, motors=motors)
    nodes = tr.nodes(params.strut_length)[:, -1]
    r = float(params.strut_radius)
    resting = ct.resting_face(ct.clearance(nodes, terrain, r), r)
    return np.array([resting[b] == f and gravity_frame(nodes[b], int(f))[3] > 0 for b, f in enumerate(faces)])
