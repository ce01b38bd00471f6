"""Shared set-up of the SDO sensor tests: the sensors section of the SDO
spacecraft file (sim/spacecraft/sdo.yaml), validated, and small geometry helpers built on scipy
(the oracle for rotations, DESIGN.md "Where checks come from")."""
from pathlib import Path

import numpy as np
import yaml
from scipy.spatial.transform import Rotation

from sim.spacecraft.sensor_models import SensorSuite

YAML_PATH = Path(__file__).parent.parent / "sim" / "spacecraft" / "sdo.yaml"
SUITE = SensorSuite.model_validate(yaml.safe_load(YAML_PATH.read_text())["sensors"])
DT = 0.2                                   # seed 001 "DeltaV": 200-msec control cycle
ARCSEC = np.pi / 180 / 3600
ARCMIN = np.pi / 180 / 60
Q_IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def quat(rotation: Rotation) -> np.ndarray:
    return rotation.as_quat(scalar_first=True)


def rotated_toward(v, toward, angle_rad) -> np.ndarray:
    """v turned by angle_rad in the plane of v and toward (toward side)."""
    v = np.asarray(v, float) / np.linalg.norm(v)
    axis = np.cross(v, toward)
    axis /= np.linalg.norm(axis)
    return Rotation.from_rotvec(axis * angle_rad).apply(v)


def random_unit_vectors(rng, n) -> np.ndarray:
    v = rng.standard_normal((n, 3))
    return v / np.linalg.norm(v, axis=1)[:, None]


def no_faults(n_units, n_slots) -> np.ndarray:
    return np.zeros((n_units, n_slots))
