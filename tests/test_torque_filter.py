"""Torque-command filters (seed 001 "Attitude control modes", "Inertial mode",
"Science mode"): the run-time biquad kernel against scipy.signal as the oracle
(sosfilt, sosfreqz, sosfilt_zi), and the designs against their specs."""
import numpy as np
import pytest
from pydantic import ValidationError
from scipy import signal

from sim.fsw.filter_design import design_sos, make_torque_filter_params
from sim.fsw.torque_filter import (BANK_INERTIAL, BANK_SCIENCE, BANKS, MAX_SECTIONS, filter_torque,
                                   make_torque_filter_state, preload_torque_filter, reset_torque_filter)
from sim.spacecraft import load_spacecraft
from sim.spacecraft.filter_models import ButterworthSpec, EllipticSpec, TorqueFilters, load_torque_filters

SC = load_spacecraft("sdo")
DT = SC.timing.control_dt_s              # seed 001 "DeltaV": 200-msec control cycle
FS = 1.0 / DT
NYQ = 0.5 * FS
FILTERS = load_torque_filters("sdo")
PARAMS = make_torque_filter_params(FILTERS, DT)
CASES = [(b, i) for b in range(len(BANKS)) for i in range(3)]
SPECS = {(b, i): getattr(FILTERS, BANKS[b]).per_axis()[i] for b, i in CASES}


def _sos(bank, axis):
    return PARAMS.sos[bank, axis]


def _run(x, bank, params=PARAMS, state=None):
    """Drive the kernel with x (n, 3); returns (y (n, 3), state)."""
    s = make_torque_filter_state() if state is None else state
    y = np.empty_like(x)
    for k in range(len(x)):
        filter_torque(x[k], params, s, bank, y[k])
    return y, s


def _db(h):
    return 20 * np.log10(np.abs(h))


def test_seed001_filter_types_per_mode_and_axis():
    # seed 001 "Inertial mode": "a second-order elliptical filter"
    for spec in FILTERS.inertial.per_axis():
        assert (spec.kind, spec.order) == ("elliptic", 2)
    # seed 001 "Science mode": 2nd-order elliptic on X, 2nd-order low pass on Y, 3rd-order elliptic on Z
    sci = FILTERS.science
    assert (sci.x.kind, sci.x.order) == ("elliptic", 2)
    assert (sci.y.kind, sci.y.order) == ("butterworth", 2)
    assert (sci.z.kind, sci.z.order) == ("elliptic", 3)
    assert PARAMS.sos.shape == (2, 3, MAX_SECTIONS, 6)


def test_kernel_is_scipy_sosfilt():
    """DF2T with scipy's state layout: the kernel and scipy.signal.sosfilt agree
    sample by sample on a random torque history."""
    x = np.random.default_rng(1).normal(0.0, 0.1, (600, 3))   # N m
    for bank in range(len(BANKS)):
        y, _ = _run(x, bank)
        for i in range(3):
            assert y[:, i] == pytest.approx(signal.sosfilt(_sos(bank, i), x[:, i]), abs=1e-15, rel=1e-12)


@pytest.mark.parametrize("bank, axis", CASES)
def test_kernel_frequency_response_from_impulse_fft(bank, axis):
    """FFT of the kernel's impulse response against sosfreqz of the design."""
    n = 8192
    x = np.zeros((n, 3))
    x[0] = 1.0
    y, _ = _run(x, bank)
    h_fft = np.fft.rfft(y[:, axis])
    f = np.fft.rfftfreq(n, DT)
    _, h_ref = signal.sosfreqz(_sos(bank, axis), worN=f, fs=FS)
    loud = np.abs(h_ref) > 1e-3                     # above -60 dB: compare in dB
    assert np.max(np.abs(_db(h_fft[loud]) - _db(h_ref[loud]))) < 1e-3   # dB
    assert np.max(np.abs(h_fft - h_ref)) < 1e-6


@pytest.mark.parametrize("f_Hz", [0.02, 0.3, 0.6, 1.5, 2.2])
def test_kernel_sinusoid_steady_state(f_Hz):
    """Drive every axis with a sinusoid; the steady-state amplitude and phase,
    fitted by least squares, are sosfreqz's (0.01 dB, 0.1 deg)."""
    n_settle, n = 2000, 2000
    t = np.arange(n_settle + n) * DT
    u = 0.1 * np.sin(2 * np.pi * f_Hz * t)
    basis = np.column_stack([np.sin(2 * np.pi * f_Hz * t), np.cos(2 * np.pi * f_Hz * t)])[n_settle:]
    for bank in range(len(BANKS)):
        y, _ = _run(np.repeat(u[:, None], 3, axis=1), bank)
        for i in range(3):
            (a, b), *_ = np.linalg.lstsq(basis, y[n_settle:, i] / 0.1, rcond=None)
            h = complex(a, b)  # y = A sin(wt + phi) = a sin + b cos: H = A e^{j phi} = a + j b
            _, h_ref = signal.sosfreqz(_sos(bank, i), worN=[f_Hz], fs=FS)
            assert _db(h) == pytest.approx(_db(h_ref[0]), abs=0.01)
            assert np.degrees(np.angle(h / h_ref[0])) == pytest.approx(0.0, abs=0.1)


@pytest.mark.parametrize("bank, axis", CASES)
def test_unity_dc_gain(bank, axis):
    sos = _sos(bank, axis)
    assert np.prod(sos[:, :3].sum(1) / sos[:, 3:].sum(1)) == pytest.approx(1.0, abs=1e-12)
    # the kernel passes a held torque (e.g. the integral torque, seed 000 eq. 4) unchanged
    y, _ = _run(np.full((1500, 3), 0.137), bank)
    assert y[-1, axis] == pytest.approx(0.137, abs=1e-12)


@pytest.mark.parametrize("bank, axis", [c for c in CASES if SPECS[c].kind == "elliptic"])
def test_elliptic_meets_its_spec(bank, axis):
    """Passband ripple within ripple_dB from DC to pass_Hz, the edge exactly at
    pass_Hz (prewarping), and stop_atten_dB below the passband peak from stop_Hz
    to Nyquist."""
    spec = SPECS[bank, axis]
    sos = _sos(bank, axis)
    _, hp = signal.sosfreqz(sos, worN=np.linspace(0.0, spec.pass_Hz, 2000), fs=FS)
    _, hs = signal.sosfreqz(sos, worN=np.linspace(spec.stop_Hz, NYQ, 2000), fs=FS)
    peak = _db(hp).max()
    assert peak - _db(hp).min() <= spec.ripple_dB + 1e-9
    assert _db(hp[-1]) == pytest.approx(peak - spec.ripple_dB, abs=1e-6)      # equiripple edge at pass_Hz
    assert _db(hs).max() <= peak - spec.stop_atten_dB + 1e-6   # peak sampled on a grid
    # the same filter as scipy's own digital design (scipy.signal.ellip with fs: prewarped bilinear)
    ref = signal.ellip(spec.order, spec.ripple_dB, spec.stop_atten_dB, spec.pass_Hz, fs=FS, output="sos")
    f = np.linspace(0.0, NYQ, 500)
    _, h_ref = signal.sosfreqz(ref, worN=f, fs=FS)
    _, h = signal.sosfreqz(sos, worN=f, fs=FS)
    assert np.abs(h - h_ref / h_ref[0]).max() < 1e-9


def test_butterworth_minus_3dB_at_cutoff():
    spec = FILTERS.science.y
    _, h = signal.sosfreqz(_sos(BANK_SCIENCE, 1), worN=[0.0, spec.cutoff_Hz], fs=FS)
    assert _db(h) == pytest.approx([0.0, -10 * np.log10(2)], abs=1e-9)
    _, h = signal.sosfreqz(_sos(BANK_SCIENCE, 1), worN=np.linspace(0, NYQ, 500), fs=FS)
    assert np.all(np.diff(np.abs(h)) < 0)                 # monotone: no ripple


def test_reset_restarts_from_rest():
    x = np.random.default_rng(2).normal(0.0, 0.1, (300, 3))
    _, s = _run(x, BANK_INERTIAL)
    assert np.abs(s.z).max() > 0
    reset_torque_filter(s)
    assert np.all(s.z == 0.0)
    step = np.full((200, 3), 0.05)
    y_after, _ = _run(step, BANK_SCIENCE, state=s)        # e.g. Inertial -> Science
    y_fresh, _ = _run(step, BANK_SCIENCE)
    assert np.array_equal(y_after, y_fresh)


def test_preload_passes_a_held_torque_without_transient():
    u = np.array([0.011, -0.203, 0.0168])                # N m, of the order of seed 000's integral torques
    x = np.random.default_rng(3).normal(0.0, 0.1, (300, 3))
    _, s = _run(x, BANK_INERTIAL)
    preload_torque_filter(s, PARAMS, BANK_SCIENCE, u)
    for i in range(3):   # scipy's steady-state initial conditions, times the input
        assert s.z[i] == pytest.approx(signal.sosfilt_zi(_sos(BANK_SCIENCE, i)) * u[i], abs=1e-15)
    y, _ = _run(np.tile(u, (50, 1)), BANK_SCIENCE, state=s)
    assert np.abs(y - u).max() < 1e-15


def test_fourth_order_fits_and_runs():
    """Seed 001: up to a fourth-order filter per axis: two biquads."""
    spec = EllipticSpec(kind="elliptic", order=4, pass_Hz=0.6, ripple_dB=0.5, stop_Hz=1.0, stop_atten_dB=40.0)
    block = {"inertial": {"x": spec.model_dump(), "y": None, "z": None}, "science": {}}
    p = make_torque_filter_params(TorqueFilters.model_validate(block), DT)
    x = np.random.default_rng(4).normal(0.0, 0.1, (400, 3))
    y, _ = _run(x, BANK_INERTIAL, params=p)
    assert y[:, 0] == pytest.approx(signal.sosfilt(design_sos(spec, DT), x[:, 0]), abs=1e-15, rel=1e-12)
    assert np.array_equal(y[:, 1:], x[:, 1:])             # unfiltered axes pass through
    assert np.array_equal(_run(x, BANK_SCIENCE, params=p)[0], x)


def test_bad_specs_fail_naming_the_field():
    with pytest.raises(ValidationError, match="less than or equal to 4"):
        ButterworthSpec(kind="butterworth", order=5, cutoff_Hz=0.5)
    with pytest.raises(ValidationError, match="stop_Hz"):
        EllipticSpec(kind="elliptic", order=2, pass_Hz=0.6, ripple_dB=1.0, stop_Hz=0.5, stop_atten_dB=20.0)
    beyond = EllipticSpec(kind="elliptic", order=2, pass_Hz=0.6, ripple_dB=1.0, stop_Hz=2.6, stop_atten_dB=20.0)
    with pytest.raises(ValueError, match=r"science\.z\.stop_Hz = 2\.6 Hz must be below the Nyquist"):
        design_sos(beyond, DT, "science.z")
    steep = EllipticSpec(kind="elliptic", order=2, pass_Hz=0.6, ripple_dB=1.0, stop_Hz=0.8, stop_atten_dB=30.0)
    with pytest.raises(ValueError, match="needs order 4"):
        design_sos(steep, DT)
