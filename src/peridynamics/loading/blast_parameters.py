"""Blast loading from a spherical free-air burst of TNT (Kingery & Bulmash 1984).

Blast parameters come from the Kingery-Bulmash polynomial fits for a *spherical free-air burst*
(C. N. Kingery and G. Bulmash, "Airblast parameters from TNT spherical air burst and hemispherical
surface burst", ARBRL-TR-02555, 1984), metric (SI) coefficient set as reproduced in UFC 3-340-02
(2008), Fig. 2-7.  Every quantity ``Y`` is fitted as

    log10(Y) = sum_i C_i U**i,     U = K0 + K1 log10(Z),     Z = R / W**(1/3)  [m/kg^(1/3)]

with ``R`` the stand-off (m) and ``W`` the TNT charge mass (kg).  The fits give pressures in kPa and
the *scaled* impulses (kPa ms / kg^(1/3)) and times (ms / kg^(1/3)); by Hopkinson-Cranz scaling the
physical impulses and times are the scaled values multiplied by ``W**(1/3)``.  This module returns
SI units only (Pa, Pa s, s).

This is the blast load of PD wave dispersion (n.d.), sections 4.1.2 (bar loaded by blasts) and
4.2 (ring). The paper gives only "a pressure history, negative phase ignored"; this project
reconstructs it (docs/theory_viscosity.md) as the normally reflected pressure ``P_r`` and
impulse ``I_r``, applied as a triangular pulse of the UFC fictitious duration
``t_r = 2 I_r / P_r`` (default) or as a modified Friedlander pulse; the negative phase is ignored.
The hemispherical surface-burst fits (Swisdak 1994) are deliberately *not* used (air burst).

Coefficients were taken from public implementations of the UFC 3-340-02 metric set and checked
against the independent imperial (CONWEP, ft / lb / psi) set of the same fits: after unit conversion
the two sets agree to better than 3e-6 (relative) over 0.0531 <= Z <= 40.

The pressure pulse built from these parameters is :class:`peridynamics.loading.blast.BlastPulse`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

__all__ = [
    "FIT_RANGES",
    "BlastParameters",
    "BlastRangeWarning",
    "kingery_bulmash",
]


class BlastRangeWarning(UserWarning):
    """A Kingery-Bulmash fit was evaluated (extrapolated) outside its scaled-distance range."""


@dataclass(frozen=True)
class _Fit:
    """One fit segment: log10(Y) = sum_i C_i U**i, U = K0 + K1 log10(Z), zmin <= Z <= zmax."""

    k0: float
    k1: float
    c: tuple[float, ...]
    zmin: float
    zmax: float

    def __call__(self, z: float) -> float:
        u = self.k0 + self.k1 * math.log10(z)
        return float(10.0 ** np.polynomial.polynomial.polyval(u, self.c))


# Kingery & Bulmash (1984) spherical free-air burst, metric coefficients (UFC 3-340-02 Fig. 2-7).
# Units of the fitted Y: kPa (pressures), kPa ms / kg^(1/3) (impulses), ms / kg^(1/3) (times).
_U_PRESSURE = (-0.214362789151, 1.35034249993)

_FITS: dict[str, tuple[_Fit, ...]] = {
    # incident (side-on) peak overpressure P_so [kPa], 0.0531 <= Z <= 40
    "incident_pressure": (
        _Fit(
            *_U_PRESSURE,
            c=(
                2.611368669,
                -1.69012801396,
                0.00804973591951,
                0.336743114941,
                -0.00516226351334,
                -0.0809228619888,
                -0.00478507266747,
                0.00793030472242,
                0.0007684469735,
            ),
            zmin=0.0531,
            zmax=40.0,
        ),
    ),
    # normally reflected peak pressure P_r [kPa], 0.0531 <= Z <= 40
    "reflected_pressure": (
        _Fit(
            *_U_PRESSURE,
            c=(
                3.22958031387,
                -2.21400538997,
                0.035119031446,
                0.657599992109,
                0.0141818951887,
                -0.243076636231,
                -0.0158699803158,
                0.0492741184234,
                0.00227639644004,
                -0.00397126276058,
            ),
            zmin=0.0531,
            zmax=40.0,
        ),
    ),
    # scaled incident impulse I_s / W^(1/3) [kPa ms / kg^(1/3)], two segments, 0.0531 <= Z <= 40
    "incident_impulse": (
        _Fit(
            2.34723921354,
            3.24299066475,
            c=(
                2.38830516757,
                -0.443749377691,
                0.168825414684,
                0.0348138030308,
                -0.010435192824,
            ),
            zmin=0.0531,
            zmax=0.792,
        ),
        _Fit(
            -1.75305660315,
            2.30629231803,
            c=(
                1.55197227115,
                -0.40463292088,
                -0.0142721946082,
                0.00912366316617,
                -0.0006750681404,
                -0.00800863718901,
                0.00314819515931,
                0.00152044783382,
                -0.0007470265899,
            ),
            zmin=0.792,
            zmax=40.0,
        ),
    ),
    # scaled normally reflected impulse I_r / W^(1/3) [kPa ms / kg^(1/3)], 0.0531 <= Z <= 40
    "reflected_impulse": (
        _Fit(
            -0.204004553231,
            1.37882996018,
            c=(2.55875660396, -0.903118886091, 0.101771877942, -0.0242139751146),
            zmin=0.0531,
            zmax=40.0,
        ),
    ),
    # scaled time of arrival t_a / W^(1/3) [ms / kg^(1/3)], 0.0531 <= Z <= 40
    "arrival_time": (
        _Fit(
            -0.253273111999,
            1.37407043777,
            c=(
                0.0720707787637,
                1.36456871214,
                -0.0570035692784,
                -0.182832224796,
                0.0118851436014,
                0.0432648687627,
                -0.0007997367834,
                -0.00436073555033,
            ),
            zmin=0.0531,
            zmax=40.0,
        ),
    ),
    # scaled positive-phase duration t_0 / W^(1/3) [ms / kg^(1/3)], three segments, 0.147 <= Z <= 40
    "positive_duration": (
        _Fit(
            2.26367268496,
            5.11588554305,
            c=(
                -0.686608550419,
                0.164953518069,
                0.127788499497,
                0.00291430135946,
                0.00187957449227,
                0.0173413962543,
                0.00269739758043,
                -0.00361976502798,
                -0.00100926577934,
            ),
            zmin=0.147,
            zmax=0.888,
        ),
        _Fit(
            -1.33361206714,
            9.2996288611,
            c=(
                0.23031841078,
                -0.0297944268969,
                0.0306329542941,
                0.018340557407,
                -0.0173964666286,
                -0.00106321963576,
                0.0056206003128,
                0.0001618217499,
                -0.0006860188944,
            ),
            zmin=0.888,
            zmax=2.28,
        ),
        _Fit(
            -3.13005805346,
            3.1524725364,
            c=(
                0.621036276475,
                0.0967031995552,
                -0.00801302059667,
                0.00482705779732,
                0.00187587272287,
                -0.00246738509321,
                -0.000841116668,
                0.0006193291052,
            ),
            zmin=2.28,
            zmax=40.0,
        ),
    ),
}

#: Validity range (Z_min, Z_max) in m/kg^(1/3) of each Kingery-Bulmash free-air fit.
FIT_RANGES: dict[str, tuple[float, float]] = {
    name: (segs[0].zmin, segs[-1].zmax) for name, segs in _FITS.items()
}


def _evaluate(name: str, z: float) -> float:
    """Fitted (scaled) value of quantity ``name`` at ``z``; below/above the range the first/last
    segment is extrapolated."""
    segs = _FITS[name]
    for seg in segs[:-1]:
        if z < seg.zmax:
            return seg(z)
    return segs[-1](z)


def _positive_finite(value: float, name: str, unit: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number > 0 ({unit}), got {value!r}") from None
    if not math.isfinite(x) or x <= 0.0:
        raise ValueError(f"{name} must be a finite number > 0 ({unit}), got {value!r}")
    return x


@dataclass(frozen=True)
class BlastParameters:
    """Kingery-Bulmash free-air blast parameters for one charge and stand-off, in SI units.

    Attributes
    ----------
    charge_kg : float
        TNT charge mass W (kg).
    standoff_m : float
        Stand-off (distance from the charge centre) R (m).
    scaled_distance : float
        Z = R / W**(1/3) (m/kg^(1/3)).
    reflected_pressure_Pa : float
        Normally reflected peak pressure P_r (Pa).
    reflected_impulse_Pa_s : float
        Normally reflected positive-phase impulse I_r (Pa s).
    incident_pressure_Pa : float
        Incident (side-on) peak overpressure P_so (Pa).
    incident_impulse_Pa_s : float
        Incident positive-phase impulse I_s (Pa s).
    arrival_time_s : float
        Time of arrival of the shock t_a (s).
    positive_duration_s : float
        Positive-phase duration t_0 (s).
    extrapolated : tuple of str
        Names of the quantities (``"reflected_pressure"``, ``"reflected_impulse"``,
        ``"incident_pressure"``, ``"incident_impulse"``, ``"arrival_time"``,
        ``"positive_duration"``) whose fit was evaluated outside its Z range (see ``FIT_RANGES``).
    """

    charge_kg: float
    standoff_m: float
    scaled_distance: float
    reflected_pressure_Pa: float
    reflected_impulse_Pa_s: float
    incident_pressure_Pa: float
    incident_impulse_Pa_s: float
    arrival_time_s: float
    positive_duration_s: float
    extrapolated: tuple[str, ...] = ()

    @property
    def reflected_duration_s(self) -> float:
        """UFC 3-340-02 fictitious reflected duration t_r = 2 I_r / P_r (s)."""
        return 2.0 * self.reflected_impulse_Pa_s / self.reflected_pressure_Pa

    def as_dict(self) -> dict:
        """Plain-Python (JSON-serialisable) dict: floats in SI units, ``extrapolated`` as a list."""
        return {
            "charge_kg": float(self.charge_kg),
            "standoff_m": float(self.standoff_m),
            "scaled_distance": float(self.scaled_distance),
            "reflected_pressure_Pa": float(self.reflected_pressure_Pa),
            "reflected_impulse_Pa_s": float(self.reflected_impulse_Pa_s),
            "reflected_duration_s": float(self.reflected_duration_s),
            "incident_pressure_Pa": float(self.incident_pressure_Pa),
            "incident_impulse_Pa_s": float(self.incident_impulse_Pa_s),
            "arrival_time_s": float(self.arrival_time_s),
            "positive_duration_s": float(self.positive_duration_s),
            "extrapolated": list(self.extrapolated),
        }


def kingery_bulmash(charge_kg: float, standoff_m: float) -> BlastParameters:
    """Blast parameters of a spherical free-air burst of TNT (Kingery & Bulmash 1984).

    Evaluates the Kingery-Bulmash free-air polynomials (UFC 3-340-02 Fig. 2-7; the blast
    loads of PD wave dispersion (n.d.), section 4.1.2, as reconstructed in
    docs/theory_viscosity.md)

        log10(Y) = sum_i C_i U**i,  U = K0 + K1 log10(Z),  Z = R / W**(1/3)  (m/kg^(1/3)),

    and converts to SI with Hopkinson-Cranz scaling:

        P = Y_P * 1e3                       (kPa -> Pa)
        I = Y_I * W**(1/3)                  (kPa ms / kg^(1/3) -> Pa s; 1 kPa ms = 1 Pa s)
        t = Y_t * W**(1/3) * 1e-3           (ms / kg^(1/3) -> s)

    Fit ranges (m/kg^(1/3)): P_so, P_r, I_r, t_a: 0.0531-40; I_s: 0.0531-0.792 and 0.792-40;
    t_0: 0.147-0.888, 0.888-2.28 and 2.28-40.

    Parameters
    ----------
    charge_kg : float
        TNT-equivalent charge mass W (kg), finite and > 0.
    standoff_m : float
        Distance R from the charge centre (m), finite and > 0.

    Returns
    -------
    BlastParameters
        Pressures in Pa, impulses in Pa s, times in s.

    Raises
    ------
    ValueError
        If ``charge_kg`` or ``standoff_m`` is not a finite positive number.

    Warns
    -----
    BlastRangeWarning
        Once, when Z lies outside the range of one or more fits.  Those quantities are still
        evaluated (polynomial extrapolation, increasingly unreliable away from the range; e.g. t_0
        collapses below Z ~ 0.05) and listed in ``BlastParameters.extrapolated``.
    """
    w = _positive_finite(charge_kg, "charge_kg", "kg")
    r = _positive_finite(standoff_m, "standoff_m", "m")
    w13 = float(np.cbrt(w))
    z = r / w13

    scaled = {name: _evaluate(name, z) for name in _FITS}
    extrapolated = tuple(name for name, (zmin, zmax) in FIT_RANGES.items() if not zmin <= z <= zmax)
    if extrapolated:
        details = ", ".join(
            f"{name} [{FIT_RANGES[name][0]:g}, {FIT_RANGES[name][1]:g}]" for name in extrapolated
        )
        warnings.warn(
            f"Kingery-Bulmash free-air fits extrapolated at scaled distance Z = {z:.4g} m/kg^(1/3) "
            f"(W = {w:g} kg, R = {r:g} m) outside the valid Z range of: {details}",
            BlastRangeWarning,
            stacklevel=2,
        )

    return BlastParameters(
        charge_kg=w,
        standoff_m=r,
        scaled_distance=z,
        reflected_pressure_Pa=scaled["reflected_pressure"] * 1e3,
        reflected_impulse_Pa_s=scaled["reflected_impulse"] * w13,
        incident_pressure_Pa=scaled["incident_pressure"] * 1e3,
        incident_impulse_Pa_s=scaled["incident_impulse"] * w13,
        arrival_time_s=scaled["arrival_time"] * w13 * 1e-3,
        positive_duration_s=scaled["positive_duration"] * w13 * 1e-3,
        extrapolated=extrapolated,
    )
