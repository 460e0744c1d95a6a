"""The bending actuator's linear model (§bending-actuator) with python-control: heating power of
wire A to the deflection at the laser, for design: its first resonance, and the heating-pulse
frequency up to which the tip still follows the pulses.

    C dT/dt = P - G T                                  (wire A's lumped model, §thermal-model)
    eps = g T                                          (its hysteresis, linearised: g the secant
                                                        of the steady minor loop, F(T_hi, T_lo) /
                                                        (T_hi - T_lo), §forc-identification)
    J theta'' + c theta' + K theta = e E_A A g T       (beams and both wires, `bending.actuator`)
    y = lever(z) theta

T is the rise above ambient, C = m c_p, G = h A_s, K = EI / L + e^2 A (E_A + E_B) / L_w. The band
[T_lo, T_hi] is the linear thermal model's own under the pulse train: mean rise P_on d / G, each
pulse adding P_on t_on / C.
"""
from __future__ import annotations

import math
from typing import Any

import control as ct
import numpy as np
from scipy.optimize import brentq

from musclesim.components.bending import actuator, beam
from musclesim.components.sma import thermal
from musclesim.components.sma.reference_wire import ReferenceWire

BENDING_DESIGN = {
    "T_amb": 20.0,  # C, room temperature
    "voltage": 5.0,  # V, pulse amplitude (§bending-actuator)
    "frequency": 4.0,  # Hz, the study's pulse frequency (§bending-actuator)
    "duty": 0.05,  # 12.5 ms per 250 ms (§bending-actuator)
    "height": 17e-3,  # m, the laser (§bending-actuator)
    # the tip "follows" the pulses while the swing of its first harmonic (peak to peak) is at
    # least this share of its mean deflection: at 1 it comes back to rest between pulses
    "follow_ratio": 1.0,
}


def operating_point(d: dict[str, Any], layout: actuator.WireLayout,
                    wire_p: thermal.ThermalParams, wire: ReferenceWire) -> dict[str, Any]:
    """Wire A's band [C], its strain secant g [1/K] and modulus [Pa] under the pulse train of the
    design `d` (module equation), for the wires' `layout`, wire A's thermal parameters `wire_p`
    and hysteresis `wire`; resistance at the band's martensite fraction."""
    sigma = layout.pretension / thermal.cross_section(wire_p)
    eps_max = float(wire.eps_max(sigma))
    G = wire_p.h * thermal.lateral_surface(wire_p)
    C = thermal.heat_capacity(wire_p)
    xi, band = 1.0, (d["T_amb"], d["T_amb"])
    for _ in range(20):  # resistance and band settle together
        R = thermal.resistance(xi, wire_p)
        P_on = R * (d["voltage"] / (R + layout.series_resistance)) ** 2
        mean = d["T_amb"] + P_on * d["duty"] / G
        jump = P_on * d["duty"] / d["frequency"] / C
        band = (mean - jump / 2, mean + jump / 2)
        xi = thermal.martensite_fraction(float(wire.F(band[1], 30.0, sigma)), eps_max)
    g = float(wire.F(band[1], band[0], sigma)) / (band[1] - band[0])
    return {"band": band, "P_on": P_on, "strain_slope": g,
            "modulus": actuator.modulus(xi, layout), "xi": xi, "stress": sigma}


def bending_system(beam_p: beam.BeamParams, layout: actuator.WireLayout,
                   wire_p: thermal.ThermalParams, op: dict[str, Any],
                   height: float) -> ct.StateSpace:
    """python-control state space from wire A's heating power [W] to the deflection at `height`
    [m] of beams `beam_p`, wires `layout` and wire A's thermal parameters `wire_p` at operating
    point `op` (`operating_point`'s); states: temperature rise [K], cap rotation [rad], its rate
    [rad/s]."""
    area = thermal.cross_section(wire_p)
    C = thermal.heat_capacity(wire_p)
    G = wire_p.h * thermal.lateral_surface(wire_p)
    J = beam.modal_inertia(beam_p)
    K = stiffness(beam_p, layout, area, op["modulus"])
    c = beam.damping_coefficient(cold_stiffness(beam_p, layout, area), beam_p)
    drive = layout.offset * op["modulus"] * area * op["strain_slope"]  # N m per K
    A = [[-G / C, 0.0, 0.0], [0.0, 0.0, 1.0], [drive / J, -K / J, -c / J]]
    B = [[1.0 / C], [0.0], [0.0]]
    Cm = [[0.0, beam.lever(height, beam_p), 0.0]]
    return ct.ss(A, B, Cm, [[0.0]], inputs=["P"], outputs=["tip"], states=["T", "theta", "omega"])


def stiffness(beam_p: beam.BeamParams, layout: actuator.WireLayout, area: float,
              modulus_a: float) -> float:
    """Rotational stiffness [N m/rad] of the beams `beam_p` and both taut wires (`layout`, of
    cross-section `area` [m2]), wire A at `modulus_a` [Pa] and wire B martensitic."""
    wires = layout.offset ** 2 * area * (modulus_a + layout.modulus_martensite) / layout.length
    return beam.rotational_stiffness(beam_p) + wires


def cold_stiffness(beam_p: beam.BeamParams, layout: actuator.WireLayout, area: float) -> float:
    """Rotational stiffness [N m/rad] of beams `beam_p` with both wires (`layout`, cross-section
    `area` [m2]) cold (martensite)."""
    return stiffness(beam_p, layout, area, layout.modulus_martensite)


def follow_ratio(sys: ct.StateSpace, f: float | np.ndarray, duty: float) -> float | np.ndarray:
    """Swing of the tip's first harmonic (peak to peak) over its mean deflection (system `sys`)
    under a pulse train of frequency `f` [Hz] (a number or an array) and `duty` d:
    4 sin(pi d) |G(j 2 pi f)| / (pi d G(0))."""
    gain = np.abs(np.asarray(sys(2j * math.pi * np.asarray(f, dtype=float)))).ravel()
    ratio = 4 * math.sin(math.pi * duty) * gain / (math.pi * duty * float(ct.dcgain(sys)))
    return float(ratio[0]) if np.ndim(f) == 0 else ratio


def follow_frequency(sys: ct.StateSpace, duty: float, ratio: float,
                     f_max: float = 1e4) -> float | None:
    """Lowest pulse frequency [Hz] at which `follow_ratio` of `sys` under pulses of `duty` falls
    to `ratio` (None: not below `f_max`)."""
    grid = np.logspace(-3, math.log10(f_max), 2000)
    values = np.asarray(follow_ratio(sys, grid, duty)) - ratio
    for k in range(1, len(grid)):
        if values[k - 1] > 0 >= values[k]:
            return float(brentq(lambda f: follow_ratio(sys, f, duty) - ratio,
                                grid[k - 1], grid[k], xtol=1e-9))
    return None


def bending(design: dict[str, Any] | None = None, beam_p: beam.BeamParams | None = None,
            layout: actuator.WireLayout | None = None) -> dict[str, Any]:
    """The linear model of the default bending actuator (or of beams `beam_p` and wires `layout`)
    and what it says for design; `design` overrides settings of `BENDING_DESIGN`.

    Returns
    -------
    dict
        ``resonance``: undamped first resonance [Hz] with both wires cold (the free actuator)
        and with wire A at the band's modulus (python-control's poles), the damped peak of the
        tip's response [Hz] and its damping ratio; ``thermal``: wire A's time constant [s],
        corner [Hz], band [C], P_on [W]; ``follow``: the pulse frequency [Hz] up to which the
        tip follows the pulses (see BENDING_DESIGN) and the ratio at the design frequency;
        ``dc_gain`` [m/W]; ``design``: the settings used.
    """
    d = {**BENDING_DESIGN, **(design or {})}
    beam_p = beam_p or beam.BeamParams()
    layout = layout or actuator.WireLayout()
    wire_p = actuator.wire_thermal(layout.length)
    op = operating_point(d, layout, wire_p, ReferenceWire())
    sys = bending_system(beam_p, layout, wire_p, op, d["height"])
    area = thermal.cross_section(wire_p)
    wn, zeta, _ = ct.damp(sys, doprint=False)
    k = int(np.argmax(wn * (zeta < 1)))  # the oscillating pair
    omega = np.logspace(2, 4.5, 4000)
    mag = np.abs(sys(1j * omega)).ravel()
    tau = thermal.time_constant(wire_p)
    return {
        "system": "bending", "reference": "§bending-actuator", "design": d,
        "resonance": {
            "cold_undamped": beam.natural_frequency(cold_stiffness(beam_p, layout, area), beam_p),
            "undamped": float(wn[k]) / (2 * math.pi), "damping_ratio": float(zeta[k]),
            "peak": float(omega[int(np.argmax(mag * (omega > 0.5 * wn[k])))]) / (2 * math.pi)},
        "thermal": {"time_constant": tau, "corner": 1 / (2 * math.pi * tau),
                    "band": list(op["band"]), "P_on": op["P_on"],
                    "strain_slope": op["strain_slope"]},
        "follow": {"frequency": follow_frequency(sys, d["duty"], d["follow_ratio"]),
                   "ratio_at_design": follow_ratio(sys, d["frequency"], d["duty"])},
        "dc_gain": float(ct.dcgain(sys)),
    }


def format_bending(report: dict[str, Any]) -> str:
    """Human-readable summary of a `bending` report `report`."""
    d, r, th, fo = report["design"], report["resonance"], report["thermal"], report["follow"]
    follow = "none below 10 kHz" if fo["frequency"] is None else f"{fo['frequency']:.2f} Hz"
    return "\n".join([
        f"Bending actuator (§bending-actuator): wire A's heating power -> deflection at "
        f"{d['height'] * 1e3:g} mm; pulses {d['voltage']:g} V, {d['duty'] * 100:g} % at "
        f"{d['frequency']:g} Hz",
        f"  first resonance: {r['cold_undamped']:.1f} Hz (wires cold), {r['undamped']:.1f} Hz "
        f"undamped at the band, peak {r['peak']:.1f} Hz, damping ratio {r['damping_ratio']:.3f}",
        f"  wire A: tau {th['time_constant']:.3f} s (corner {th['corner']:.3f} Hz), band "
        f"{th['band'][0]:.1f}-{th['band'][1]:.1f} C, {th['P_on']:.3f} W while on, minor-loop "
        f"slope {th['strain_slope'] * 1e3:.3f}e-3 / K",
        f"  the tip follows the pulses (first-harmonic swing >= {d['follow_ratio']:g} x mean "
        f"deflection) up to {follow}; at {d['frequency']:g} Hz the ratio is "
        f"{fo['ratio_at_design']:.3f}",
        f"  static gain {report['dc_gain'] * 1e3:.4f} mm/W"])
