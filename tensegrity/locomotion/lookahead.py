"""The planner's model: every roll is simulated before the robot makes it (issue 30 item 2;
docs/design.md §6).

One method on every ground. The candidate actions of a step come from GENERATORS (the plan's
candidates in the workspace's order toward the target, then every other action, then, with
`locomotion.optimised_actions`, the optimised weight vectors of `actuation.candidates`, and with
`locomotion.cable_actions` those of the 24 cables one by one; another
source of actions is one more entry), each rolled with the brake (`brake.Brake`, which acts only
where the unbraked robot is predicted not to stand) and, where that brake acts, also without it
and, lazily, with it kept on (`kept`). `foresee` simulates candidates from the robot's current
state with the run's own controller, all in one batch, so each result is the roll the run would
make. `choose` keeps a roll that lands on another face (`lands`: on a face, its CoG moved at most
SLIDE m, else a tumble) at a state the run has not been at since its CoG last came closer to the
goal (`memory.Memory`), and ranks those by `progress.rolls_to_goal`, the rolls still needed by the
robot's own stride and lift (`progress.stride`). The horizon grows by cost alone: the workspace's
best candidate first; where it is not acceptable, the lazy generators' actions go next (`LAZY`:
computed only then, 0.13-0.24 s of CPU a step on 20 deg; the optimised ones are solved on the
robot's own pose and gravity, the plan's on the flat workspace), and the horizon grows to 2, 4,
... up to `lookahead` candidates, then all of them, only while none is acceptable.
A candidate's simulation ends as soon as its outcome is decided (`decided.until_decided`): its CoG
more than SLIDE m away (a tumble or slide); unbraked, at rest at the top of its ramp without
rolling, or its ramp given up on its face (`control.roll_controller`'s `foresee`). A roll that
lands on another face, and a braked one, runs to its settled end.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence
from dataclasses import replace

import numba
import numpy as np

from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from ..workspace.lookup import Workspace
from .actuation import World
from .actuation import cables as _cables
from .actuation import optimised as _optimised
from .ahead import Ramp, lockstep_ahead
from .brake import Brake, escape
from .braked import Braked
from .control import RollResult, action_weights, roll_controller
from .decided import SLIDE, until_decided
from .lockstep import Obs, Record, widths
from .memory import Memory
from .plan import Candidate, Plan
from .settings import RollSettings

__all__ = [
    "Act",
    "GENERATORS",
    "LAZY",
    "Memory",
    "SLIDE",
    "World",
    "acts",
    "choose",
    "foresee",
    "kept",
    "lands",
    "moved",
    "verdicts",
    "weights_of",
]

# One candidate roll: (1-based pairs, braked), or (pairs, braked, weights) with a weight vector (12,)
# per pair or (24,) per cable as a tuple (largest 1; pairs: its nonzero entries; `control.action_weights`).
Act = tuple


def _planned(workspace: Workspace, face: int, nodes: np.ndarray, pl: Plan, target: dict, world=None) -> list[Candidate]:
    """The plan's candidates in its order (`plan.plan`): those predicted to roll toward the target first."""
    return list(pl.candidates)


def _pairs(
    workspace: Workspace, face: int, nodes: np.ndarray, pl: Plan, target: dict, world=None
) -> list[tuple[int, ...]]:
    """Every action not in the plan, in `brake.escape`'s order."""
    return escape(workspace, face, nodes, {c.pairs for c in pl.candidates}, **target)


# Sources of candidate actions, tried in this order: f(workspace, face, nodes (12, 3) m, plan,
# target, world: World | None) -> Candidates, pair tuples (1-based) or weight vectors (12,) or (24,).
# A new kind of action is one more entry. Those in LAZY are computed only where the first is not acceptable.
GENERATORS: list[Callable] = [_planned, _pairs, _optimised, _cables]
LAZY: set[Callable] = {_optimised, _cables}


def _act(a) -> tuple:
    """A generator's action as (pairs,) or (pairs, weights tuple): a weight vector (24,) per cable
    with both cables of each pair equal is the (12,) one per pair, and a weight vector of ones and
    zeros is the pairs action it equals."""
    if isinstance(a, Candidate):
        return (a.pairs,)
    if isinstance(a, np.ndarray) and a.shape == (topo.N_CABLES,):
        one, two = a[topo.PAIR_CABLES[:, 0]], a[topo.PAIR_CABLES[:, 1]]
        if not np.array_equal(one, two):
            return (action_weights(None, a)[0], tuple(float(x) for x in a))
        a = one
    if isinstance(a, np.ndarray) and a.shape == (12,):
        pairs = tuple(int(q) + 1 for q in np.flatnonzero(a > 0))
        return (pairs,) if np.all((a == 0) | (a == 1)) else (pairs, tuple(float(x) for x in a))
    return (tuple(int(q) for q in a),)


def acts(
    workspace: Workspace,
    face: int,
    nodes: np.ndarray,
    pl: Plan,
    target: dict,
    brake: Brake | None,
    world: World | None = None,
    lazy: bool = False,
) -> list[Act]:
    """The step's candidate rolls in the order to simulate them: every generator's actions (not
    in LAZY; lazy: only those in LAZY), each once, braked (if the run brakes); then, where the
    brake acts on this face, each unbraked; lazy, the brake kept (`kept`) after the braked ones."""
    seen: list[tuple] = []
    for gen in GENERATORS:
        if (gen in LAZY) != lazy:
            continue
        for a in gen(workspace, face, nodes, pl, target, world):
            a = _act(a)
            if a not in seen:
                seen.append(a)
    first = [(a[0], brake is not None, *a[1:]) for a in seen]
    acting = brake is not None and brake.active(face, nodes)
    if acting:
        first += [(a[0], False, *a[1:]) for a in seen]
    return first[: len(seen)] + (kept(pl) if acting else []) + first[len(seen) :] if lazy else first


def kept(pl: Plan) -> list[Act]:
    """The plan's braked actions again with their brake kept on (a weight vector of ones: no
    planned pressure, `foresee`): each braked pairs action hands its brake over to the roll as
    the level nears the plan's pressure (`brake.ramp_fade`), a prediction for the unbraked robot.
    Where only the brake holds the robot, that prediction is the fall the brake prevents (the
    CoG projection outside at 0 MPa: the brake let go at once) and every twin, braked or not,
    tumbles; kept on, the brake holds while the action ramps (docs/planner_evaluation.md, "The
    brake kept on where the plan's pressure is the fall it prevents")."""
    return [
        (c.pairs, True, tuple(float(x) for x in action_weights(c.pairs)[1]))
        for c in pl.candidates
        if np.isfinite(c.pressure)
    ]


def weights_of(act: Act) -> np.ndarray | None:
    """The weight vector (12,) or (24,) of the action `act`, None for a pairs action."""
    return np.asarray(act[2], float) if len(act) > 2 else None


def foresee(
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    obs: Obs,
    todo: Sequence[Act],
    max_pressure: float,
    brake: Brake | None,
    expect: dict[tuple[int, ...], float],
) -> list[RollResult]:
    """The rolls (one RollResult per candidate of `todo`) the robot observed in `obs` (with its
    `state`) would make, each with the run's settings `s`, a copy of `brake` if braked, and the
    planned pressure `expect[pairs]` MPa (NaN if absent or weighted), simulated together from
    the same state, on one numba thread: each kernel call advances a batch by one check
    interval only, and a second OpenMP thread spins between calls, which costs 2.4 times the CPU
    of one thread (156 candidates on a 20 deg slope, docs/planner_evaluation.md). The ramps,
    braked or not, are simulated several intervals per call (`ahead.lockstep_ahead`), to the same bits.
    Each result holds its final `state` and, as a one-sample `record`, its last levels (where a next
    roll goes on from; `choose` drops both). Raises SimulationError if a simulation blows up."""
    if obs.state is None:
        raise ValueError("the observation carries no state to simulate from")
    if not todo:
        return []
    state = d.State.concat([obs.state] * len(todo))
    acting: list[bool] = []  # whether the brake acts on the start face (`Brake.active`, the same for all)
    ramps: list[Ramp | None] = [None] * len(todo)  # the candidates' ramps (`ahead.lockstep_ahead`)

    def make(b: int, ob: Obs):
        ob = Obs(obs.t, ob.nodes, ob.gap, ob.face, obs.speed, obs.pressure.copy(), cog=ob.cog)
        pairs, braked, w = todo[b][0], todo[b][1], weights_of(todo[b])
        brk = None
        if braked and brake is not None:
            if not acting and ob.face is not None:
                acting.append(brake.active(ob.face, ob.nodes))
            if acting[:1] != [False]:  # where it does not act, the roll is the unbraked one (roll_controller)
                brk = copy.deepcopy(brake, {id(brake.workspace): brake.workspace})  # the workspace shared
        planned = expect.get(pairs, float("nan")) if w is None else float("nan")
        ctl = roll_controller(
            params, s, ob, pairs, max_pressure, brk, planned, weights=w, foresee=True, brake_acts=(acting or [None])[0]
        )
        aw = widths(action_weights(pairs, w)[1], ob.pressure)  # the controller's width
        if brk is None:
            ramps[b] = Ramp(aw, s, max_pressure)
        elif ob.face is not None:  # its brake: the controller's own choice, made on a copy
            held = copy.deepcopy(brk, {id(brake.workspace): brake.workspace}).for_face(ob.face, ob.nodes)
            ramps[b] = Braked(aw, s, max_pressure, held, planned)
        return until_decided(ctl, ob, pairs, w, s, max_pressure, brk is not None)

    threads = numba.get_num_threads()
    numba.set_num_threads(1)  # see the docstring
    try:
        out = lockstep_ahead(params, terrain, state, make, s, ramps)
    finally:
        numba.set_num_threads(threads)
    return [replace(res, state=st, record=_last(ob)) for (res, ob), st in out]


def _last(ob: Obs) -> Record:
    """The one sample of a candidate's last observation: where a next roll goes on from (its levels)."""
    return Record(np.array([ob.t]), ob.nodes[None], np.asarray(ob.pressure, float)[None], np.array([ob.face or 0]))


def moved(r: RollResult) -> float:
    """How far the roll `r` moved the CoG horizontally, m (a roll: 0.1-0.3 m)."""
    return float(np.linalg.norm(np.subtract(r.cog_after, r.cog_before)[:2]))


def lands(r: RollResult, slide: float = SLIDE) -> bool:
    """The roll `r` ends on a face, its CoG moved at most `slide` m horizontally (`moved`; more
    is a slide, which counts as a tumble)."""
    return r.face_after is not None and moved(r) <= slide


def verdicts(simulated: Sequence[RollResult], memory: Memory) -> str:
    """How the rolls `simulated` fail, in words: how many tumble or slide (not `lands`), do not
    roll, return to a state in `memory`, or land without progress."""
    tumble = sum(not lands(r) for r in simulated)
    stay = sum(lands(r) and not r.rolled for r in simulated)
    back = sum(lands(r) and r.rolled and memory.seen(r.face_after, r.cog_after) for r in simulated)
    rest = len(simulated) - tumble - stay - back
    return f"{tumble} tumble or slide, {stay} do not roll, {back} return, {rest} land elsewhere"


def choose(
    params: Params,
    terrain: Terrain,
    s: RollSettings,
    obs: Obs,
    todo: Sequence[Act],
    max_pressure: float,
    brake: Brake | None,
    expect: dict[tuple[int, ...], float],
    cost: Callable[[RollResult], float],
    memory: Memory,
    now: float = np.inf,
    more: Callable[[], Sequence[Act]] | None = None,
    onward: Callable[[RollResult], bool] | None = None,
    known: Callable[..., list[RollResult]] | None = None,
) -> tuple[list[Act], tuple[RollResult, ...]]:
    """A run's step: simulate the candidates `todo` in order in batches of growing horizon (the
    first; then 2, 4, ... up to s.lookahead; then all), `more()`'s actions put next after the first
    where it is not acceptable (called only then), stopping at
    the first batch after which one is acceptable: it rolls onto another face, `lands` (no tumble, no
    slide), at a state not in `memory`, and makes progress (`cost` below `now`, the cost of staying).
    Return the s.max_attempts acceptable candidates of least `cost` (if none makes progress, those
    acceptable otherwise: a detour, which the memory keeps from cycling; if none is, those that return
    to a state with an acceptable roll not taken, `Memory.opens`: a backtrack) and every roll simulated,
    in order; the acceptable ones are recorded in `memory`. A tumble or a slide is never returned.
    Progress counts only where `onward` judges the landing no dead end (asked best first), and the best
    such candidate goes first. `known` (`foreseen.Foreseen`) simulates in place of `foresee`, reusing rolls."""
    todo = list(todo)
    simulated: list[RollResult] = []
    fine: list[int] = []
    rank = lambda i: (round(cost(simulated[i]), 9), i)  # noqa: E731
    judged: dict[int, bool] = {}  # candidate: its landing is no dead end (`onward`, asked once, best first)
    good = lambda i: judged[i] if i in judged else judged.setdefault(i, onward is None or onward(simulated[i]))  # noqa: E731
    for k in [*_doubling(s.lookahead), None]:
        if more is not None and (simulated or not todo):  # the first is not acceptable: the lazy actions next
            todo[len(simulated) : len(simulated)] = [a for a in more() if a not in todo]
            more = None
        k = len(todo) if k is None else k
        if k <= len(simulated):
            continue
        simulated += (known or foresee)(params, terrain, s, obs, todo[len(simulated) : k], max_pressure, brake, expect)
        fine = [
            i for i, r in enumerate(simulated) if r.rolled and lands(r) and not memory.seen(r.face_after, r.cog_after)
        ]
        if any(cost(simulated[i]) < now and good(i) for i in sorted(fine, key=rank)):
            break
    memory.record([(simulated[i].face_after, simulated[i].cog_after) for i in fine])
    if not fine:  # a dead end: a roll back to an open state (`Memory.opens`) is a backtrack
        fine = [i for i, r in enumerate(simulated) if r.rolled and lands(r) and memory.opens(r.face_after, r.cog_after)]
    fine.sort(key=rank)
    k = next((n for n, i in enumerate(fine) if good(i)), 0)
    fine = fine[k : k + 1] + fine[:k] + fine[k + 1 :]
    return [todo[i] for i in fine[: s.max_attempts]], tuple(replace(r, state=None, record=None) for r in simulated)


def _doubling(n: int) -> list[int]:
    """The horizons up to `n`: 1, 2, 4, ... doubling, then n (each batch as large as all before
    it: at most twice the candidates the first acceptable one needs are simulated)."""
    return [1] + [2**j for j in range(1, n.bit_length()) if 2**j < n] + [n]
