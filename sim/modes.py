"""The six SDO attitude control modes (seed 001 "Attitude control modes") and
the transitions between them (seed 001 Fig. 3, derived from the text: the
sentence behind each edge is quoted in docs/modes.md).

A transition has a cause: GROUND (a command), FDC (failure detection and
correction) or AUTONOMOUS (an objective met). ALLOWED maps (from, to) to the
causes that may take that edge; any other pair is refused.
"""
from enum import IntEnum


class Mode(IntEnum):
    SUNACQ = 0
    INERTIAL = 1
    SCIENCE = 2
    DELTAH = 3
    DELTAV = 4
    SAFEHOLD = 5


GROUND, FDC, AUTONOMOUS = "ground", "fdc", "autonomous"
CAUSES = (GROUND, FDC, AUTONOMOUS)

M = Mode
ALLOWED: dict[tuple[Mode, Mode], tuple[str, ...]] = {
    # into Inertial: "All of the other main processor modes have the capability to enter this mode"
    (M.SUNACQ, M.INERTIAL): (GROUND,),
    (M.SCIENCE, M.INERTIAL): (GROUND, FDC),
    (M.DELTAH, M.INERTIAL): (GROUND, FDC, AUTONOMOUS),
    (M.DELTAV, M.INERTIAL): (GROUND, FDC, AUTONOMOUS),
    # Science: autonomous with the autonomy flag, or commanded; out via Inertial, or to SunAcq/Safehold
    (M.INERTIAL, M.SCIENCE): (GROUND, AUTONOMOUS),
    (M.SCIENCE, M.SUNACQ): (GROUND, FDC),
    # DeltaV: "strictly ground commanded" in
    (M.INERTIAL, M.DELTAV): (GROUND,),
    # DeltaH: from Inertial, or from SunAcq (tip-off contingency); back to where it came from
    (M.INERTIAL, M.DELTAH): (GROUND,),
    (M.SUNACQ, M.DELTAH): (GROUND,),
    (M.DELTAH, M.SUNACQ): (GROUND, FDC, AUTONOMOUS),
    # SunAcq as the main processor's coarse fallback (choice: docs/modes.md)
    (M.INERTIAL, M.SUNACQ): (GROUND, FDC),
    (M.DELTAV, M.SUNACQ): (FDC,),
    # the ground brings the main processor back from Safehold through SunAcq (choice: docs/modes.md)
    (M.SAFEHOLD, M.SUNACQ): (GROUND,),
}
# Safehold from every other mode by FDC or ground (seed 001 names Science -> Safehold; the rest: docs/modes.md)
for _m in (M.SUNACQ, M.INERTIAL, M.SCIENCE, M.DELTAH, M.DELTAV):
    ALLOWED[(_m, M.SAFEHOLD)] = (GROUND, FDC)

IMPLEMENTED = tuple(Mode)
# a run may start in these; the thruster modes need their entry command's arguments
INITIAL_MODES = (Mode.SUNACQ, Mode.INERTIAL, Mode.SCIENCE, Mode.SAFEHOLD)


def refusal(current: Mode, target: Mode, cause: str) -> str:
    """Why current -> target by `cause` is not allowed, or "" when it is."""
    if target == current:
        return f"already in {current.name}"
    if target not in IMPLEMENTED:
        return f"{target.name} is not implemented; implemented modes: {', '.join(m.name for m in IMPLEMENTED)}"
    causes = ALLOWED.get((current, target))
    if causes is None:
        reachable = [t.name for (f, t) in ALLOWED if f == current and t in IMPLEMENTED]
        return (f"{current.name} -> {target.name} is not an allowed transition; from {current.name}: "
                f"{', '.join(reachable) or 'none'}")
    if cause not in causes:
        return f"{current.name} -> {target.name} is taken by {' or '.join(causes)}, not {cause}"
    return ""
