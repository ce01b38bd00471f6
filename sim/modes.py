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

ALLOWED: dict[tuple[Mode, Mode], tuple[str, ...]] = {
    (Mode.INERTIAL, Mode.SCIENCE): (GROUND, AUTONOMOUS),
    (Mode.SCIENCE, Mode.INERTIAL): (GROUND, FDC),
}

# Modes whose flight software exists so far; the rest arrive with their issues.
IMPLEMENTED = (Mode.INERTIAL, Mode.SCIENCE)


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
