"""Two rolls ahead, where no single roll is acceptable (issue 30 item 2; docs/design.md §6).

`lookahead.choose` refuses every roll of a step that tumbles, slides, does not roll, or returns
to a state the run has been at (`lookahead.Memory`). On a steep slope that can leave nothing: the
only rolls that land under control go back where the robot was, or across with no progress. Then
`two_rolls` looks one roll further, by the same simulation and the same ranking: from each safe
landing of the step's simulated rolls (rolled, no tumble, no slide; returns and detours included;
one per face and place), it simulates the next step's candidates, all landings in one batched
`lookahead.foresee` call per horizon (1, 2, 4, ... up to `lookahead`, then all, while no sequence
makes progress), and returns the first rolls of the acceptable sequences, least cost of the second
landing first. A sequence is acceptable when its second roll is, with the first landing added to
the memory: so every sequence ends at a state the run has not been at, and a route still cannot
cycle; it ends stuck or at the step limit instead.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from .brake import Brake
from .control import RollResult
from .lockstep import Obs
from .lookahead import Act, Memory, _doubling, foresee, lands
from .settings import RollSettings

__all__ = ["landings", "two_rolls"]


def landings(simulated: Sequence[RollResult], cost: Callable[[RollResult], float], radius: float) -> list[int]:
    """Indices of the safe landings of `simulated` (rolled, `lands`), one per face and place (CoGs
    within `radius` m are one place), the least `cost` of each first."""
    safe = sorted((i for i, r in enumerate(simulated) if r.rolled and lands(r)), key=lambda i: (cost(simulated[i]), i))
    out: list[int] = []
    for i in safe:
        r = simulated[i]
        if not any(
            simulated[j].face_after == r.face_after
            and np.linalg.norm(np.subtract(simulated[j].cog_after, r.cog_after)[:2]) < radius
            for j in out
        ):
            out.append(i)
    return out


def _onward(params, terrain, s: RollSettings, land: list, nxt: list, max_pressure: float, memory: Memory, cost, enough):
    """The least `cost` of an acceptable roll onward from each landing j of `land` ((RollResult,
    Obs, Brake) of `lookahead.foresee(landings=True)`; nxt[j]: its candidates and planned
    pressures; acceptable with the landing added to `memory`), simulated in one batched call per
    horizon (1, 2, 4, ... s.lookahead, then all) until enough(costs) holds. Returns the costs
    {j: cost} and the number of rolls simulated."""
    mem = []
    for r, _, _ in land:
        m = Memory(memory.radius, list(memory.states))
        m.add(r.face_after, r.cog_after)
        mem.append(m)
    best: dict[int, float] = {}
    done, count = [0] * len(land), 0
    for k in [*_doubling(s.lookahead), max(len(a) for a, _ in nxt)]:
        batch = [(j, a) for j, (acts, _) in enumerate(nxt) for a in acts[done[j] : k]]
        done = [max(d, min(k, len(a))) for d, (a, _) in zip(done, nxt)]
        if not batch:
            continue
        js = [j for j, _ in batch]
        starts, brakes, expects = [land[j][1] for j in js], [land[j][2] for j in js], [nxt[j][1] for j in js]
        res = foresee(params, terrain, s, starts, [a for _, a in batch], max_pressure, brakes, expects)
        count += len(res)
        for j, r in zip(js, res):
            if r.rolled and lands(r) and not mem[j].seen(r.face_after, r.cog_after):
                best[j] = min(best.get(j, np.inf), cost(r))
        if enough(best):
            break
    return best, count


def two_rolls(
    params,
    terrain,
    s: RollSettings,
    obs: Obs,
    todo: Sequence[Act],
    simulated: Sequence[RollResult],
    max_pressure: float,
    brake: Brake | None,
    expect: dict,
    cost: Callable[[RollResult], float],
    memory: Memory,
    now: float,
    after: Callable[[Obs, Brake | None], tuple[list[Act], dict]],
) -> tuple[list[Act], int]:
    """The first rolls of the best acceptable two-roll sequences from the robot `obs`, at most
    s.max_attempts, each a candidate of `todo` (whose rolls `simulated` are in the same order);
    after(landing Obs, the run's brake there) gives the next step's candidates and planned
    pressures there. Returns them and the number of rolls simulated."""
    firsts = landings(simulated, cost, memory.radius)
    if not firsts:
        return [], 0
    land = foresee(params, terrain, s, obs, [todo[i] for i in firsts], max_pressure, brake, expect, landings=True)
    nxt = [after(ob, bk) for _, ob, bk in land]
    best, count = _onward(
        params, terrain, s, land, nxt, max_pressure, memory, cost, lambda b: any(c < now for c in b.values())
    )
    order = sorted(best, key=lambda j: (round(best[j], 9), j))
    return [todo[firsts[j]] for j in order[: s.max_attempts]], count + len(land)


def alive(
    params,
    terrain,
    s: RollSettings,
    obs: Obs,
    chosen: Sequence[Act],
    max_pressure: float,
    brake: Brake | None,
    expect: dict,
    cost: Callable[[RollResult], float],
    memory: Memory,
    after: Callable[[Obs, Brake | None], tuple[list[Act], dict]],
) -> tuple[list[Act], int]:
    """`chosen` (the acceptable rolls, best first) with the first whose landing is not a dead end
    (it has an acceptable roll onward, `_onward`) moved to the front, the rolls before it (dead
    ends) after the others; unchanged if every one is a dead end. Returns them, at most
    s.max_attempts, and the number of rolls simulated."""
    count = 0
    for n, act in enumerate(chosen):
        land = foresee(params, terrain, s, obs, [act], max_pressure, brake, expect, landings=True)
        if not (land[0][0].rolled and lands(land[0][0])):  # not as simulated before: a dead end here
            count += 1
            continue
        best, k = _onward(params, terrain, s, land, [after(land[0][1], land[0][2])], max_pressure, memory, cost, bool)
        count += k + 1
        if best:
            return [*chosen[n:], *chosen[:n]][: s.max_attempts], count
    return list(chosen[: s.max_attempts]), count
