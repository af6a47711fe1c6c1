"""The run's memory (`locomotion.memory.Memory`, docs/design.md §6): a roll may not return to a
state the run stood at since its CoG last came horizontally closer to the goal than ever before.
Progress (a new least distance) clears the states, so a route stranded in a dead end it reached by
progress goes back the way it came (the two stuck terrain 0.05 m runs of
docs/planner_evaluation.md, 435913 and 11470); without progress the route still cannot cycle; and
a cost that changes from face to face (on a slope each face has its own lift) is not progress."""

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion import lookahead
from tensegrity.locomotion.control import RollResult
from tensegrity.locomotion.lockstep import Obs
from tensegrity.locomotion.memory import Memory
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

TRAVEL = 0.2  # m: one roll's travel in the toy routes below; the memory's radius is half of it
GOAL = np.zeros(2)  # m: the goal of the toy routes


def test_a_new_least_distance_clears_the_memory_and_nothing_else_does():
    mem = Memory(TRAVEL / 2, GOAL)
    mem.add(1, np.array([1.0, 0.0]))
    mem.add(2, np.array([1.2, 0.0]))  # farther: remembered with the first
    assert mem.seen(1, np.array([1.05, 0.0])) and mem.seen(2, np.array([1.2, 0.0]))
    assert not mem.seen(1, np.array([1.2, 0.0])) and not mem.seen(3, np.array([1.0, 0.0]))
    mem.add(3, np.array([0.0, 1.0]))  # as near as the nearest, not nearer: remembered too
    assert mem.seen(1, np.array([1.0, 0.0])) and len(mem.states) == 3
    mem.add(4, np.array([0.6, 0.0]))  # nearer than ever: only it is remembered
    assert mem.nearest == 0.6 and [f for f, _ in mem.states] == [4]
    assert not mem.seen(1, np.array([1.0, 0.0])) and not mem.seen(2, np.array([1.2, 0.0]))
    assert mem.seen(4, np.array([0.6, 0.0]))
    plain = Memory(TRAVEL / 2)  # without a goal (a direction, edges) nothing is forgotten
    for f in (3, 2, 1):
        plain.add(f, np.array([0.0, float(f)]))
    assert len(plain.states) == 3 and plain.nearest == np.inf


# Toy routes: places (face, CoG x, y m) joined by rolls, each moving the CoG less than SLIDE; the
# goal at the origin; a place's cost is its distance over TRAVEL (`progress.rolls_to_goal` on flat
# ground) plus, where given, its face's own term `lift[face]` (as a slope's lift adds to it).
# `lookahead.foresee` is replaced by the graph: action (k,) rolls the robot onto place k.


def _route(monkeypatch, places, exits, start, lift=None, rolls=20, look=False):
    """The places a route visits from `start` until it is stuck, the run's steps as `drive` makes
    them: add the state to the memory, `choose` at the cost of staying, roll the least-cost
    acceptable roll (with `look`, the landings judged as `drive.onward` judges them: a place with
    no exit is a dead end)."""
    here = {"at": start}
    lift = lift or {}

    def foresee(params, terrain, s, obs, todo, max_pressure, brake, expect):
        f0, *c0 = places[here["at"]]
        return [
            RollResult(
                a[0],
                True,
                f0,
                places[a[0][0]][0],
                1.0,
                1.0,
                0.0,
                1.0,
                np.array([*c0, 0.0]),
                np.array([*places[a[0][0]][1:], 0.0]),
            )
            for a in todo
        ]

    def rolls_to_goal(face, xy):
        return float(np.hypot(*xy[:2])) / TRAVEL + lift.get(face, 0.0)

    monkeypatch.setattr(lookahead, "foresee", foresee)
    s = lo.RollSettings(lookahead=4, max_attempts=1)
    mem, visited = Memory(TRAVEL / 2, GOAL), [start]
    for _ in range(rolls):
        face, x, y = places[here["at"]]
        mem.add(face, np.array([x, y]))
        obs = Obs(0.0, np.zeros((12, 3)), np.zeros(12), face, 0.0)
        todo = [((k,), False) for k in exits[here["at"]]]
        now = rolls_to_goal(face, np.array([x, y]))
        cost = lambda r: rolls_to_goal(r.face_after, r.cog_after)  # noqa: E731
        onward = (lambda r: bool(exits[r.pairs[0]])) if look else None
        chosen, _ = lookahead.choose(
            Params(), Terrain.flat(), s, obs, todo, 4.8, None, {}, cost, mem, now, None, onward
        )
        if not chosen:
            break
        here["at"] = chosen[0][0][0]
        visited.append(here["at"])
    return visited


def test_a_dead_end_reached_by_progress_is_left_the_way_it_came(monkeypatch):
    """A corridor A -> B -> C; C, the closest yet, has one exit: back to B. On a memory of every
    state ever stood at the route ends stuck at C; with progress clearing it, the route goes
    back to B, then by the detour E to the goal G."""
    places = {0: (1, 1.0, 0.0), 1: (2, 0.8, 0.0), 2: (3, 0.6, 0.0), 3: (4, 0.85, 0.3), 4: (5, 0.45, 0.35)}
    exits = {0: [1], 1: [0, 2, 3], 2: [1], 3: [1, 4], 4: []}  # G (4): closer than C, the route's end
    assert _route(monkeypatch, places, exits, 0) == [0, 1, 2, 1, 3, 4]


def test_a_route_without_progress_cannot_cycle(monkeypatch):
    """A ring of four places, the start the closest: no roll makes progress, so nothing is
    forgotten; the route goes once round and ends stuck beside its start (no return to it), not
    round and round to the roll limit."""
    places = {0: (1, 1.0, 0.0), 1: (2, 1.2, 0.2), 2: (3, 1.4, 0.0), 3: (4, 1.2, -0.2)}
    exits = {0: [1, 3], 1: [0, 2], 2: [1, 3], 3: [2, 0]}
    visited = _route(monkeypatch, places, exits, 0)
    assert len(visited) == 4 and sorted(visited) == [0, 1, 2, 3]


def test_a_lower_cost_on_another_face_is_not_progress(monkeypatch):
    """The same ring, the start the closest but on a face of high lift (3 rolls more, as a slope
    makes one face's cost differ from another's): its neighbours cost fewer rolls to go though
    they lie farther from the goal. Judged by that cost the first roll would be progress and
    clear the memory, and the route would come back to its start; judged by the distance to the
    goal nothing is forgotten, and the route ends stuck beside its start as on level ground."""
    places = {0: (1, 1.0, 0.0), 1: (2, 1.05, 0.05), 2: (3, 1.1, 0.0), 3: (4, 1.05, -0.05)}
    exits = {0: [1, 3], 1: [0, 2], 2: [1, 3], 3: [2, 0]}
    visited = _route(monkeypatch, places, exits, 0, lift={1: 3.0})
    assert visited == [0, 1, 2, 3]


def test_a_state_is_open_while_an_acceptable_landing_found_there_is_not_in_the_memory():
    mem = Memory(TRAVEL / 2, GOAL)
    mem.add(1, np.array([1.0, 0.0]))
    mem.record([(2, np.array([1.1, 0.15, 0.0])), (3, np.array([1.3, -0.2, 0.0]))])  # two exits found
    assert mem.opens(1, np.array([1.02, 0.0])) and not mem.opens(2, np.array([1.1, 0.15]))
    mem.add(2, np.array([1.1, 0.15]))  # one exit taken: the other still open
    assert mem.opens(1, np.array([1.0, 0.0]))
    mem.add(1, np.array([1.02, 0.0]))  # back again: its record is what is found now (nothing yet)
    assert not mem.opens(1, np.array([1.0, 0.0]))
    mem.record([(3, np.array([1.3, -0.2]))])
    assert mem.opens(1, np.array([1.0, 0.0]))
    mem.add(3, np.array([1.3, -0.2]))  # every exit taken: closed
    assert not mem.opens(1, np.array([1.0, 0.0]))


def test_a_dead_end_is_left_by_going_back_to_an_exit_not_taken(monkeypatch):
    """The start S, the closest, has two exits: A, the nearer, and B; A's only roll is back to S.
    No roll makes progress, so the memory holds S at A: without backtracking the route ends stuck
    at A; S is open (B was found acceptable there and not taken), so the route goes back to S,
    then by B to the goal G."""
    places = {0: (1, 1.0, 0.0), 1: (2, 1.1, 0.15), 2: (3, 1.3, -0.2), 3: (4, 0.9, -0.1)}
    exits = {0: [1, 2], 1: [0], 2: [3], 3: []}
    assert _route(monkeypatch, places, exits, 0) == [0, 1, 0, 2, 3]


def test_backtracking_between_two_open_states_ends_without_cycling(monkeypatch):
    """S (the closest) finds A and B and takes A; A finds C and D and takes C; C's only roll is
    back to A (as A1), where D is no longer found, and A1's only roll is back to S (as S1), where
    B is no longer found, and S1's only roll is back to A1. S still has B untaken and A still has
    D: on records kept from the first stands the route would go S1, A1, S1, ... to the roll
    limit. Standing at a state again replaces its record by what is found now (nothing), so the
    route backtracks to A1 and S1 once each and ends stuck at S1."""
    places = {
        0: (1, 1.0, 0.0),  # S
        1: (2, 1.1, 0.15),  # A
        2: (3, 1.3, -0.2),  # B
        3: (4, 1.2, 0.35),  # C
        4: (5, 1.35, 0.3),  # D
        5: (2, 1.12, 0.15),  # A1: the state A again
        6: (1, 1.02, 0.0),  # S1: the state S again
    }
    exits = {0: [1, 2], 1: [3, 4], 2: [], 3: [5], 4: [], 5: [6], 6: [5]}
    assert _route(monkeypatch, places, exits, 0) == [0, 1, 3, 5, 6]


def test_a_landing_that_is_a_dead_end_is_not_rolled_to_first(monkeypatch):
    """From S two rolls make progress: to A, the nearer, a dead end (no roll from it: on a slope,
    a face only the brake holds, where every roll tumbles), and to B, which leads on to the goal G.
    Ranked by cost alone the route rolls to A and ends stuck there (S is not open: nothing rolls
    back to it); with the landings judged, A goes after B, and the route arrives by B."""
    places = {0: (1, 1.0, 0.0), 1: (2, 0.7, 0.0), 2: (3, 0.8, 0.1), 3: (4, 0.5, 0.1)}
    exits = {0: [1, 2], 1: [], 2: [3], 3: []}
    assert _route(monkeypatch, places, exits, 0) == [0, 1]
    assert _route(monkeypatch, places, exits, 0, look=True) == [0, 2, 3]
