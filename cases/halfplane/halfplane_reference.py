#!/usr/bin/env python3
"""Continuum reference for the half-plane cases: the exact linear-elastic response of an
orthotropic (or isotropic) half-plane y < 0 to the Eq. 21 strip load on its free surface,

    sigma_yy(x, 0, t) = -p0 H(a - |x|) exp(-alpha t^2) sin(beta t),  sigma_xy(x, 0, t) = 0,

evaluated by wavenumber-frequency integration. This is Lamb's (1904) problem for a strip load,
solved the way his integral representation is evaluated numerically by the discrete
wavenumber method (Bouchon and Aki 1977) with a complex frequency:

  * Fourier transforms in x (wavenumber k) and t (frequency w). For each (k, w) the half-plane
    carries two plane waves exp(i (k x + q y + w t)) whose vertical wavenumbers solve the
    Christoffel equation of the 2D orthotropic continuum (stiffness c11, c12, c22, c66 in the
    x-y frame; units Pa, kg/m^3):
        c22 c66 q^4 + [c66 (c66 k^2 - X) + c22 (c11 k^2 - X) - (c12 + c66)^2 k^2] q^2
            + (c11 k^2 - X)(c66 k^2 - X) = 0,            X = rho w^2,
    taking the root with Im q < 0 (waves that go down or decay with depth).
  * The amplitudes of the two waves follow from the traction conditions sigma_xy = 0 and
    sigma_yy = -p on y = 0 (a 2x2 system per (k, w)).
  * w is replaced by w - i eps (the time signal is damped by exp(-eps t) before the transform
    and the result multiplied by exp(eps t) after), which moves the Rayleigh pole off the real
    axis; eps T = 10 over the period T of the time grid keeps the wrap-around below 1e-4.
    The x period L is long enough that no wave of the periodic images reaches a station
    within the requested window.

Plane stress of an isotropic solid is the same problem with c11 = c22 = E/(1 - nu^2),
c12 = nu c11, c66 = E/(2 (1 + nu)) (i.e. plane strain with lambda replaced by
2 lambda mu / (lambda + 2 mu)). For an isotropic solid the surface response reduces to Lamb's
closed form  u_y(k, 0, w) = i P q_L (w^2 / c_T^2) / (mu R),
R = (k^2 - q_T^2)^2 + 4 k^2 q_L q_T; `--selftest` checks the general code against it, and
its Rayleigh speed against ../../../shared/reference/lattice_reference.py when present.

Units: SI (m, s, Pa, kg/m^3); displacements in m, velocities in m/s. Needs numpy only.

    python3 halfplane_reference.py --selftest
"""
import sys

import numpy as np


def _modes(c, rho, k, wc):
    """Vertical wavenumbers q (Im q < 0) and polarisations of the two waves: arrays [2, ...]."""
    c11, c12, c22, c66 = c
    X = rho * wc * wc
    k2 = k * k
    A = c22 * c66
    B = c66 * (c66 * k2 - X) + c22 * (c11 * k2 - X) - (c12 + c66) ** 2 * k2
    C = (c11 * k2 - X) * (c66 * k2 - X)
    disc = np.sqrt(B * B - 4 * A * C)
    Q = np.stack([(-B - disc) / (2 * A), (-B + disc) / (2 * A)])
    q = np.sqrt(Q)
    q = np.where(q.imag > 0, -q, q)
    # Polarisation from either row of the Christoffel matrix, whichever is better conditioned
    # (the first degenerates for the shear wave at k = 0, the second for the longitudinal one).
    v1x = (c12 + c66) * k * q
    v1y = -(c11 * k2 + c66 * q * q - X)
    v2x = c66 * k2 + c22 * q * q - X
    v2y = -(c12 + c66) * k * q
    first = np.abs(v1x) ** 2 + np.abs(v1y) ** 2 >= np.abs(v2x) ** 2 + np.abs(v2y) ** 2
    ax = np.where(first, v1x, v2x)
    ay = np.where(first, v1y, v2y)
    return q, ax, ay


def surface_transfer(c, rho, k, wc):
    """Amplitudes of the two waves for a unit surface pressure (sigma_yy = -1 on y = 0)."""
    c11, c12, c22, c66 = c
    q, ax, ay = _modes(c, rho, k, wc)
    syy = 1j * (c12 * k * ax + c22 * q * ay)
    sxy = 1j * c66 * (q * ax + k * ay)
    det = sxy[0] * syy[1] - sxy[1] * syy[0]
    A0 = sxy[1] * 1.0 / det          # [[sxy0, sxy1], [syy0, syy1]] [A0, A1] = [0, -1]
    A1 = -sxy[0] * 1.0 / det
    return q, ax, ay, A0, A1


def strip_response(c, rho, a, p0, alpha, beta, stations, t_end, dt=0.25e-6, dx=0.5e-3,
                   length=None, period=None):
    """Displacement and velocity histories at stations [(x, y), ...] (y <= 0) for the strip
    load p0 H(a - |x|) exp(-alpha t^2) sin(beta t), t >= 0. Returns (t, u, v) with t [s] the
    times 0, dt, ... up to t_end and u, v [m, m/s] arrays of shape (stations, 2, times)."""
    c11, c12, c22, c66 = c
    c_max = np.sqrt(max(c11, c22) / rho)
    reach = max(abs(x) for x, _ in stations) + a
    if length is None:  # no wave of a periodic image reaches a station before t_end
        length = 2.0 * (reach + c_max * t_end) + 0.05
    n = int(2 ** np.ceil(np.log2(length / dx)))
    if period is None:
        period = 4.0 * t_end
    m = int(2 ** np.ceil(np.log2(period / dt)))
    period = m * dt
    eps = 10.0 / period
    t = np.arange(m) * dt
    f = np.exp(-alpha * t * t) * np.sin(beta * t) * np.exp(-eps * t)
    F = np.fft.rfft(f)                                   # (m//2 + 1,)
    w = 2 * np.pi * np.fft.rfftfreq(m, dt)
    k = (2 * np.pi * np.fft.fftfreq(n, dx))[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        P = p0 * np.where(k == 0, 2 * a, 2 * np.sin(k * a) / np.where(k == 0, 1, k))
    xs = np.array([x for x, _ in stations])
    ys = np.array([y for _, y in stations])
    # Inverse transform in x at the stations only: (1 / (n dx)) sum_k U exp(i k x).
    E = np.exp(1j * xs[:, None] * k[None, :, 0]) / (n * dx)            # (stations, n)
    Ux = np.zeros((len(stations), len(w)), complex)
    Uy = np.zeros_like(Ux)
    chunk = 64
    for j0 in range(0, len(w), chunk):  # frequency by frequency block, to bound the memory
        wc = (w[j0:j0 + chunk] - 1j * eps)[None, :]
        q, ax, ay, A0, A1 = surface_transfer(c, rho, k, wc)
        A0 = A0 * P * F[None, j0:j0 + chunk]
        A1 = A1 * P * F[None, j0:j0 + chunk]
        for i, y in enumerate(ys):
            e0 = A0 * np.exp(1j * q[0] * y)
            e1 = A1 * np.exp(1j * q[1] * y)
            Ux[i, j0:j0 + chunk] = E[i] @ (e0 * ax[0] + e1 * ax[1])
            Uy[i, j0:j0 + chunk] = E[i] @ (e0 * ay[0] + e1 * ay[1])
    keep = t <= t_end + 0.5 * dt
    grow = np.exp(eps * t[keep])
    wc = (w - 1j * eps)[None, :]
    u = np.stack([np.fft.irfft(U, m, axis=1)[:, keep] * grow for U in (Ux, Uy)], axis=1)
    v = np.stack([np.fft.irfft(U * 1j * wc, m, axis=1)[:, keep] * grow for U in (Ux, Uy)], axis=1)
    return t[keep], u, v


def rayleigh_speed(c, rho):
    """Rayleigh speed along x [m/s]: the real w/k where the surface system is singular
    (bisection on |det| of the traction matrix, evaluated with a tiny negative Im w)."""
    c11, c12, c22, c66 = c
    k = 1.0

    def det(speed):
        q, ax, ay = _modes(c, rho, np.array(k), np.array(speed * k - 1e-12j))
        syy = 1j * (c12 * k * ax + c22 * q * ay)
        sxy = 1j * c66 * (q * ax + k * ay)
        return sxy[0] * syy[1] - sxy[1] * syy[0]

    speeds = np.linspace(0.5, 0.99999, 4000) * np.sqrt(min(c66, c11) / rho)
    vals = np.array([abs(det(s)) for s in speeds])
    i = int(np.argmin(vals))
    lo, hi = speeds[max(i - 1, 0)], speeds[min(i + 1, len(speeds) - 1)]
    for _ in range(100):  # golden-section search for the minimum of |det|
        m1, m2 = lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo)
        if abs(det(m1)) < abs(det(m2)):
            hi = m2
        else:
            lo = m1
    return 0.5 * (lo + hi)


def isotropic_plane_stress(E, nu):
    """c11, c12, c22, c66 [Pa] of an isotropic solid in plane stress."""
    f = E / (1 - nu * nu)
    return (f, nu * f, f, E / (2 * (1 + nu)))


MATERIAL_B = (5.0961e9, 1.2256e9, 3.5359e9, 1.2198e9)  # Pa; rho = 1244 kg/m^3


def selftest():
    ok = True
    # 1. General solver against Lamb's closed form (isotropic, plane stress, nu = 0.25).
    E, nu, rho = 4.0e9, 0.25, 1244.0
    c = isotropic_plane_stress(E, nu)
    mu = c[3]
    cl, ct = np.sqrt(c[0] / rho), np.sqrt(mu / rho)
    k = np.linspace(-8000, 8000, 161)[:, None]
    wc = (np.linspace(1e4, 6e6, 157) - 1j * 2e4)[None, :]
    q, ax, ay, A0, A1 = surface_transfer(c, rho, k, wc)
    uy = A0 * ay[0] + A1 * ay[1]
    qL = np.sqrt(wc ** 2 / cl ** 2 - k ** 2)
    qL = np.where(qL.imag > 0, -qL, qL)
    qT = np.sqrt(wc ** 2 / ct ** 2 - k ** 2)
    qT = np.where(qT.imag > 0, -qT, qT)
    R = (k ** 2 - qT ** 2) ** 2 + 4 * k ** 2 * qL * qT
    lamb = 1j * qL * wc ** 2 / ct ** 2 / (mu * R)  # unit pressure: sigma_yy = -1
    err = np.max(np.abs(uy - lamb) / np.abs(lamb))
    print("Lamb closed form vs general solver: max relative difference %.2e" % err)
    ok &= err < 1e-9
    # 2. Rayleigh speed of material B against the project's reference script.
    cr = rayleigh_speed(MATERIAL_B, 1244.0)
    print("Rayleigh speed of material B: %.2f m/s (physics.md: 936.7 m/s)" % cr)
    ok &= abs(cr - 936.7) < 0.1
    try:
        import os
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                        "..", "..", "..", "shared", "reference"))
        import lattice_reference as lr
        ref = lr.rayleigh_speed(MATERIAL_B, 1244.0)
        print("  lattice_reference.rayleigh_speed: %.3f m/s" % ref)
        ok &= abs(cr - ref) < 0.05
    except ImportError:
        pass
    # 3. A wide load (a >> the distance waves travel) is a plane wave: v_y = -p / (rho c_22).
    t, u, v = strip_response(MATERIAL_B, 1244.0, 2.0, 1e6, 5.689e9, 2659.0, [(0.0, -0.02)], 60e-6)
    c22 = np.sqrt(MATERIAL_B[2] / 1244.0)
    tt = t - 0.02 / c22
    plane = np.where(tt > 0, -1e6 * np.exp(-5.689e9 * tt * tt) * np.sin(2659.0 * tt) / (1244.0 * c22), 0.0)
    # The arrival is a kink that falls between samples: judge the RMS error.
    err = np.sqrt(np.mean((v[0, 1] - plane) ** 2)) / np.max(np.abs(plane))
    print("plane-wave limit: RMS of v_y - (-p / (rho c_22)) over the peak = %.2e" % err)
    ok &= err < 2e-3
    print("selftest", "passed" if ok else "FAILED")
    return ok


if __name__ == "__main__":
    if "--selftest" in sys.argv:
        sys.exit(0 if selftest() else 1)
    sys.exit(__doc__)
