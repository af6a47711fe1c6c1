"""The paper's facts (Lin, Li and Zhao; `../shared/paper.txt`), constants only: what the
validation checks, the demonstration runs, the design studies and the figures reproduce.
Node, pair and face numbers are the paper's, 1-based; the canonical contact faces are
`physics.topology.CONTACT_FACES`.
"""

from __future__ import annotations

START_FACE = (9, 10, 12)  # the robot stands on (9,10,12) throughout III.A-C and IV.B

# III.A, Fig. 7: on (9,10,12) these pairs move the CoG most, these next
LARGE_PAIRS, LESS_PAIRS = (9, 10, 12), (4, 6, 7)
FIG4_PAIRS = (4, 6, 7, 9, 10, 12)  # Fig. 4: the six pairs that move the CoG on (9,10,12)
FIG6_PAIR, FIG6_MAX_PRESSURE = 10, 2.4  # Fig. 6: #10's CoG cloud, 0.4-2.4 MPa

TIP_PRESSURE = 4.2  # MPa: #10 rolls the robot off (9,10,12), III.C

# IV.B, the experiment: (pair driven, edge crossed, face landed on), in turn
EXPERIMENT = ((10, (10, 12), (10, 11, 12)), (11, (10, 11), (6, 10, 11)))
EXPERIMENT_EDGES = tuple(edge for _, edge, _ in EXPERIMENT)
EDGE = {pair: edge for pair, edge, _ in EXPERIMENT}
VOLTAGE = {10: 11.1, 11: 6.0}  # V: the prototype's drive of each roll (IV.B)
