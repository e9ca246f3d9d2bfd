"""Reductions of sampled outputs over whole mesh periods.

The window holds ``N`` whole mesh periods ``T_m = 2 pi / (z1 omega1)`` sampled at ``M`` equally
spaced points per period (``N M + 1`` samples, first and last one period-multiple apart). For a
signal periodic in ``T_m`` the rectangle rule over ``N M`` samples is the exact mean of its first
``M/2 - 1`` harmonics, and the discrete Fourier transform of those samples has the mesh order
``k`` in bin ``k N``; its one-sided amplitude is ``2 |X[k N]| / (N M)``.

Mean powers come from energy differences where the FMU integrates them (``E_in``, ``E_loss``:
exact integrals of ``P_in``, ``P_loss`` over the window), not from sampled powers.
"""

from __future__ import annotations

import numpy as np


def mean_over_periods(y: np.ndarray) -> float:
    """Mean of samples over whole periods (the last sample repeats the first period phase)."""
    return float(np.mean(y[:-1]))


def peak_to_peak(y: np.ndarray) -> float:
    return float(np.max(y) - np.min(y))


def order_amplitudes(y: np.ndarray, periods: int, n_orders: int) -> list[float]:
    """One-sided amplitudes of mesh orders 1..n_orders."""
    z = y[:-1]
    spec = np.fft.rfft(z)
    scale = 2.0 / len(z)
    return [float(abs(spec[k * periods]) * scale) for k in range(1, n_orders + 1)]


def efficiency_from_energies(dE_in: float, dE_loss: float) -> float:
    """Mesh efficiency 1 - <P_loss>/<P_in> from the energies over the window."""
    if dE_in == 0.0:
        return float("nan")
    return 1.0 - dE_loss / dE_in
