"""The six SDO attitude control modes (seed 001 "Attitude control modes")."""
from enum import IntEnum


class Mode(IntEnum):
    SUNACQ = 0
    INERTIAL = 1
    SCIENCE = 2
    DELTAH = 3
    DELTAV = 4
    SAFEHOLD = 5


# Modes whose flight software exists so far; the rest arrive with their issues.
IMPLEMENTED = (Mode.INERTIAL,)
