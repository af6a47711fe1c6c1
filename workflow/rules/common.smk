# What every rule file shares: the contact cases and pairs swept, the demonstration runs, Fig. 6,
# and `cfg(stage)`, the configuration keys a stage reads (tensegrity.stages.config.STAGES): each
# rule's params carry exactly those, so editing a key re-runs the jobs that read it and no other.
from tensegrity import paper
from tensegrity.stages.config import actuator_error, stage_config

CONTACTS = config["sweep"]["contacts"]
PAIRS = config["sweep"]["pairs"]

LOCO = config["locomotion"]
LOCO_RUNS = LOCO["runs"]
PATH_RUNS = [r for r in LOCO_RUNS if r != "paper"]
SLOPE_RUN = "slope_down" if "slope_down" in LOCO_RUNS or "slope_up" not in LOCO_RUNS else "slope_up"

FIG6_PAIR = paper.FIG6_PAIR if paper.FIG6_PAIR in PAIRS else PAIRS[0]
FIG6_CONTACT = "equilateral" if "equilateral" in CONTACTS else CONTACTS[0]

# nominal.method statics: the nominal CoG files are the robot's static equilibria (stage
# nominal_statics), made without the sweeps, and Fig. 6 and the page draw no samples
NOMINAL_STATICS = config["nominal"]["method"] == "statics"


def cfg(stage):
    """The configuration keys `stage` reads (stages.config.stage_config). A stage that cannot run
    with the configured actuator gets a params function instead, which refuses it naming the key
    when its job enters the plan (before any job runs): no job of it is ever started."""
    why = actuator_error(config, stage)
    if why is None:
        return stage_config(config, stage)

    def refuse(wildcards):
        raise ValueError(why)

    return refuse
