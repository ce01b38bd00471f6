"""Torque-command filter, run time: a biquad cascade per body axis.

Seed 001 "Attitude control modes": the control torques "may be filtered with up
to a fourth-order discrete filter, with a different design possible in each
mode and for each axis of control"; the filtered torques are then distributed.
The coefficients come from sim/fsw/filter_design.py (parameter-build time).

Each axis is a cascade of MAX_SECTIONS second-order sections in Direct Form II
transposed, the structure and the state layout of scipy.signal.sosfilt
(coefficients [b0, b1, b2, a0 = 1, a1, a2]; two registers per section):

    y     = b0 x + z0
    z0'   = b1 x - a1 y + z1
    z1'   = b2 x - a2 y

Unused sections are pass-through [1, 0, 0, 1, 0, 0], so every axis runs the
same code (up to 4th order). A mode bank is a (3, MAX_SECTIONS, 6) block of
the parameters; the state is one (3, MAX_SECTIONS, 2) array, shared by the
banks, reset when the mode (and so the bank) changes:

* `reset_torque_filter`: all registers zero (the filter starts from rest).
* `preload_torque_filter`: the registers of the steady state for a constant
  input u (scipy.signal.sosfilt_zi times u), so a held torque -- the integral
  torque at a mode transition -- passes without a transient.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

MAX_SECTIONS = 2  # two biquads: up to 4th order per axis (seed 001)
BANKS = ("inertial", "science")  # bank number = index
BANK_INERTIAL, BANK_SCIENCE = 0, 1


class TorqueFilterParams(NamedTuple):
    sos: np.ndarray   # (n_banks, 3, MAX_SECTIONS, 6) [b0, b1, b2, 1, a1, a2] per bank, axis, section


class TorqueFilterState(NamedTuple):
    z: np.ndarray     # (3, MAX_SECTIONS, 2) DF2T registers per axis and section


def identity_sos(n_sections: int) -> np.ndarray:
    sos = np.zeros((n_sections, 6))
    sos[:, 0] = 1.0
    sos[:, 3] = 1.0
    return sos


def make_torque_filter_state() -> TorqueFilterState:
    return TorqueFilterState(np.zeros((3, MAX_SECTIONS, 2)))


@njit(cache=True)
def sos_step(sos, zi, x):
    """One sample through a cascade: sos (n, 6), registers zi (n, 2) updated
    in place; returns the output."""
    for k in range(sos.shape[0]):
        y = sos[k, 0] * x + zi[k, 0]
        zi[k, 0] = sos[k, 1] * x - sos[k, 4] * y + zi[k, 1]
        zi[k, 1] = sos[k, 2] * x - sos[k, 5] * y
        x = y
    return x


@njit(cache=True, inline="always")
def filter_torque(torque_B, p, s, bank, out_B):
    """Filter the commanded body torque (3,) with bank `bank`; writes out_B."""
    for i in range(3):
        out_B[i] = sos_step(p.sos[bank, i], s.z[i], torque_B[i])


@njit(cache=True)
def reset_torque_filter(s):
    """Zero every register: the filter restarts from rest."""
    s.z[:] = 0.0


@njit(cache=True)
def preload_torque_filter(s, p, bank, torque_B):
    """Registers of the steady state of bank `bank` under the constant input
    torque_B: the next outputs equal torque_B times the DC gain, with no
    transient. Per section, with input x and output y = g x (g its DC gain):
    z1 = b2 x - a2 y and z0 = y - b0 x."""
    for i in range(3):
        x = torque_B[i]
        for k in range(MAX_SECTIONS):
            c = p.sos[bank, i, k]
            y = x * (c[0] + c[1] + c[2]) / (1.0 + c[4] + c[5])
            s.z[i, k, 1] = c[2] * x - c[5] * y
            s.z[i, k, 0] = y - c[0] * x
            x = y
