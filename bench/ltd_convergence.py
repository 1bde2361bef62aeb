"""LTD against LFD on the paper grid: case T2 (NACA0010, M0.735), sine gust omega = 1 (k = 0.5).

1. Started on the LFD periodic state, one period at dt = 0.2, 0.1, 0.05: the BDF2 error against the LFD
   (magnitude and phase of Cl and Cm) and its order.
2. From rest at dt = 0.05 to s = 60: the response becomes periodic as the start-up vortex leaves the domain;
   magnitude and phase over successive periods against the LFD. Figure docs/figures/gust-ltd-lfd-T2.png.

Run: ``MPLBACKEND=Agg .venv/bin/python bench/ltd_convergence.py`` (several minutes on two cores).
"""

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cfd  # noqa: E402
from cfd.lfd import lfd_response, lfd_state  # noqa: E402


def harmonic(t, y, omega):
    M = np.stack([np.cos(omega * t), np.sin(omega * t), np.ones_like(t)], 1)
    c = np.linalg.lstsq(M, y, rcond=None)[0]
    return c[0] - 1j * c[1]


def main(omega=1.0):
    t0 = time.perf_counter()
    sol = cfd.solve_steady(cfd.c_grid(cfd.naca("0010")), 0.735, 0.0)
    lin = cfd.linearise(sol)
    H = lfd_response(lin, [omega]).H[:, 0, 0]
    gust = cfd.SineGust(angle_deg=1.0, omega=omega)
    qh = (1j * gust.amplitude) * lfd_state(lin, omega)  # u(s) = Re(i A exp(i omega s)) at x_ref = 0
    print(f"T2, sine gust omega = {omega}: LFD Cl {H[0]:.4f}, Cm {H[1]:.4f} ({time.perf_counter() - t0:.0f} s)")
    print("1. periodic start, one period")
    print("   dt     |Cl| err   arg Cl err (deg)   |Cm| err   arg Cm err (deg)   time (s)")
    prev = None
    for dt in (0.2, 0.1, 0.05):
        t1 = time.perf_counter()
        q = lambda s: (qh * np.exp(1j * omega * s)).real  # noqa: E731
        h = cfd.ltd_response(lin, gust, dt, 2 * np.pi / omega, initial=(q(-dt), q(0.0)), max_phase_error=1.0)
        U = harmonic(h.t, h.u, omega)
        G = np.array([harmonic(h.t, h.cl, omega), harmonic(h.t, h.cm, omega)]) / U
        e = np.abs(G / H - 1)
        order = "" if prev is None else f"  order {np.log2(prev / e[0]):.2f}"
        prev = e[0]
        print(f"  {dt:5.3f}  {abs(G[0]) / abs(H[0]) - 1:+.2e}   {np.degrees(np.angle(G[0] / H[0])):+.4f}"
              f"          {abs(G[1]) / abs(H[1]) - 1:+.2e}   {np.degrees(np.angle(G[1] / H[1])):+.4f}"
              f"          {time.perf_counter() - t1:.0f}{order}")
    print("2. from rest, dt = 0.05")
    t1 = time.perf_counter()
    T = 2 * np.pi / omega
    h = cfd.ltd_response(lin, gust, 0.05, 60.0)
    print(f"   {h.t.size - 1} steps in {time.perf_counter() - t1:.0f} s")
    print("   period from   |Cl|/|H|-1   arg (deg)   |Cm|/|H|-1   arg (deg)")
    for start in np.arange(0.0, 60.0 - T, T):
        m = (h.t >= start) & (h.t <= start + T)
        U = harmonic(h.t[m], h.u[m], omega)
        G = np.array([harmonic(h.t[m], h.cl[m], omega), harmonic(h.t[m], h.cm[m], omega)]) / U
        print(f"   {start:6.1f}       {abs(G[0]) / abs(H[0]) - 1:+.4f}     {np.degrees(np.angle(G[0] / H[0])):+6.2f}"
              f"      {abs(G[1]) / abs(H[1]) - 1:+.4f}     {np.degrees(np.angle(G[1] / H[1])):+6.2f}")
    fig, ax = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
    per = lambda y: (y * np.exp(1j * omega * h.t)).real  # noqa: E731
    U = 1j * gust.amplitude
    for a, y, Hk, name in ((ax[0], h.cl, H[0], "Cl"), (ax[1], h.cm, H[1], "Cm")):
        a.plot(h.t, y, "-", label="LTD from rest (dt = 0.05)")
        a.plot(h.t, per(U * Hk), "k:", label="LFD periodic response")
        a.set_ylabel(name)
    ax[0].legend(fontsize=8)
    ax[1].set_xlabel("s = U t / c")
    ax[0].set_title("T2 (NACA0010, M0.735), sine gust omega = 1, 1 deg")
    fig.tight_layout()
    (ROOT / "docs" / "figures").mkdir(parents=True, exist_ok=True)
    fig.savefig(ROOT / "docs" / "figures" / "gust-ltd-lfd-T2.png", dpi=110)


if __name__ == "__main__":
    main()
