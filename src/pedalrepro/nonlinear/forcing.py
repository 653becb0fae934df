"""The one builder of the compiled forcing (``forcing_t`` of ``pedalrepro/csrc/forcing.h``).

The simulation library (:mod:`.simulate`, ``model_library.c``) and the periodic-orbit library
(:mod:`pedalrepro.periodic`, ``periodic_library.c``) both read the pedalling forcing from this
struct: the harmonic roll and steer torques of Eq 3.14 (coefficients times ``w^2``) and/or the
prescribed leg motion of the model (``model.spec``, Fourier series plus a linear drift), with the
model's parameters.
"""

from __future__ import annotations

import ctypes

import numpy as np

__all__ = ["ForcingStruct", "fill_forcing"]


class ForcingStruct(ctypes.Structure):
    """``forcing_t`` of ``forcing.h``."""

    _fields_ = [("n_harm", ctypes.c_int), ("harm_w", ctypes.c_void_p),
                ("roll_re", ctypes.c_void_p), ("roll_im", ctypes.c_void_p),
                ("steer_re", ctypes.c_void_p), ("steer_im", ctypes.c_void_p),
                ("n_spec", ctypes.c_int), ("n_four", ctypes.c_int), ("omega", ctypes.c_double),
                ("four_re", ctypes.c_void_p), ("four_im", ctypes.c_void_p),
                ("slope", ctypes.c_void_p), ("p", ctypes.c_void_p)]


def fill_forcing(fc: ForcingStruct, model, harmonics=None, omega_rad_s: float = 0.0) -> list:
    """Fill ``fc`` with the forcing of ``model`` (a :class:`.nonlinear_model.NonlinearModel`).

    Parameters
    ----------
    fc
        The struct to fill (a :class:`ForcingStruct`, or the ``f`` field of a larger struct).
    model
        Its parameters (``p_array``) and prescribed legs (``spec`` when ``n_spec > 0``).
    harmonics, omega_rad_s
        Pedalling torques of Eq 3.14 (``n``, ``roll``, ``steer``, N m / (rad/s)^2) at cadence
        ``omega_rad_s``; none when ``harmonics`` is None or ``omega_rad_s`` is 0.

    Returns
    -------
    list
        The arrays the struct points to: keep them alive as long as the struct is used.
    """
    keep: list[np.ndarray] = []

    def ptr(a) -> int:
        a = np.ascontiguousarray(a, dtype=float)
        keep.append(a)
        return a.ctypes.data

    if harmonics is not None and omega_rad_s > 0:
        n = np.asarray(harmonics.n, dtype=float)
        w = n * omega_rad_s
        roll = np.asarray(harmonics.roll, dtype=complex) * w**2
        steer = np.asarray(harmonics.steer, dtype=complex) * w**2
        fc.n_harm = len(n)
        fc.harm_w, fc.roll_re, fc.roll_im = ptr(w), ptr(roll.real), ptr(roll.imag)
        fc.steer_re, fc.steer_im = ptr(steer.real), ptr(steer.imag)
    if model.n_spec:
        spec = model.spec
        fc.n_spec, fc.n_four, fc.omega = model.n_spec, spec.coef.shape[1], spec.omega_rad_s
        fc.four_re, fc.four_im = (ptr(a) for a in spec.harmonic_major())
        fc.slope = ptr(spec.slope)
    fc.p = ptr(model.p_array)
    return keep
