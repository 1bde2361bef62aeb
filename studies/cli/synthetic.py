"""A synthetic :class:`studies.store.results.StudyResults` without CFD: for tests, examples and the report's docs.

The "LFD" response of every case is the gust-like system of :mod:`studies.cli.demo` (a two-lag Kussner-like lift
and two lightly damped modes, input gust angle, outputs Cl and Cm per radian) sampled on McKelvey's grid with
a little complex noise; the "LTD" histories are that system's exact responses to the study's gusts (Tustin at
the simulation step). The ROMs are real :func:`sysid.identify` models at every sweep point of the study, and
their gust histories and metrics come from the same functions the runner uses
(:func:`sysid.metrics.rom_metrics`, :func:`studies.sections.gust_rom.pieces.sim_metrics`), so every table and figure of a
report can be produced and inspected before any CFD has run.

>>> from studies.cli.synthetic import synthetic_results
>>> res = synthetic_results()          # doctest: +SKIP
>>> len(res.roms), res.missing         # doctest: +SKIP
(16, [])

A whole sample report (a few seconds): ``python -m studies.cli.synthetic --out /tmp/synthetic-report``.
"""

from __future__ import annotations

import time
import warnings
from typing import Optional

import numpy as np

import sysid
from sysid.metrics import rom_metrics

from ..config.study import StudyConfig, loads_study
from ..sections.gust_rom.pieces import sim_metrics
from ..store.results import FRFRecord, LTDRecord, RomRecord, SimRecord, StudyResults

__all__ = ["SYNTHETIC_STUDY", "synthetic_config", "synthetic_results", "gust_input", "main"]

SYNTHETIC_STUDY = """
name = "synthetic"
description = "Synthetic data (studies.cli.synthetic): the studies.cli.demo gust-like system stands in for the CFD"
cases = [{ name = "synth", naca = "0010", mach = 0.735 }]
gusts = ["G3", "G6"]

[sweep]
orders = [2, 4, 6, 10]
T = ["70/(2*pi)"]
M_base = 64
M = [64, 16]

[methods.plain]

[methods.dc_stable]
dc_gain = "match"
stable = true

[simulation]
dt = 0.05
t_end = 30.0
x0 = -2.0
"""
"""The default synthetic study: one case named "synth" (its aerofoil and Mach number are labels only)."""


def synthetic_config(output_dir=None) -> StudyConfig:
    """:data:`SYNTHETIC_STUDY` validated, with its output (and store) under ``output_dir`` (default: cwd)."""
    from pathlib import Path

    base = Path(output_dir) if output_dir is not None else Path.cwd()
    # top-level keys must come before the first [table]
    text = f'output = "{base.as_posix()}"\n' + SYNTHETIC_STUDY
    return loads_study(text, source="<synthetic>", base_dir=base)


def gust_input(t, gust, x0: float) -> np.ndarray:
    """Gust angle input ``u = v_g(x_ref = 0, t) / U`` of a :class:`studies.config.cases.GustCase` (radians).

    The front is at ``x0`` at ``t = 0`` and reaches ``x_ref = 0`` at ``t = -x0`` (convective time).

    Parameters
    ----------
    t : array_like, shape (n,)
    gust : GustCase
    x0 : float

    Returns
    -------
    ndarray, shape (n,)
    """
    t = np.asarray(t, dtype=float)
    amp = np.tan(np.radians(gust.angle_deg))
    s = t + x0  # distance travelled past x_ref
    if gust.kind == "sharp_edged":
        return np.where(s >= 0.0, amp, 0.0)
    L = float(gust.length)
    inside = (s >= 0.0) & (s <= L)
    return np.where(inside, 0.5 * amp * (1.0 - np.cos(2.0 * np.pi * s / L)), 0.0)


def _simulate(model_d, u) -> np.ndarray:
    """Discrete state-space response (p, n) to input u (n,), zero initial state."""
    A, B, C, D = (np.asarray(m, dtype=float) for m in (model_d.A, model_d.B, model_d.C, model_d.D))
    x = np.zeros(A.shape[0])
    y = np.empty((C.shape[0], u.size))
    for i, ui in enumerate(u):
        y[:, i] = C @ x + D[:, 0] * ui
        x = A @ x + B[:, 0] * ui
    return y


def synthetic_results(config: Optional[StudyConfig] = None, *, noise: float = 2e-3, seed: int = 0,
                      fail: tuple = (), drop: tuple = ()) -> StudyResults:
    """A complete (or deliberately incomplete) :class:`StudyResults` built from the synthetic truth.

    Parameters
    ----------
    config : StudyConfig, optional
        Any validated study (its cases, T, M, orders, methods, gusts and simulation are used; the CFD settings
        are not). Default :func:`synthetic_config`.
    noise : float
        Complex noise on the "LFD" samples, relative to each output's peak (the ``omega = 0`` sample stays real
        and the ``omega = inf`` one exact, as from the CFD).
    seed : int
    fail : tuple of (case, M, order, method)
        Sweep points recorded as failed (``"SolverError: synthetic failure"``), to exercise the report.
    drop : tuple of (case, gust)
        LTD references left out (listed in ``missing``), with their ROM histories.

    Returns
    -------
    StudyResults
    """
    import control

    from .demo import continuous_frf, gust_like_system

    config = config or synthetic_config()
    rng = np.random.default_rng(seed)
    A, B, C, D = gust_like_system()
    truth = control.ss(A, B, C, D)
    outputs = list(config.cfd.outputs)[:2]
    sim = config.simulation
    t = np.arange(int(round(sim.t_end / sim.dt)) + 1) * sim.dt
    truth_dt = sysid.c2d_bilinear(truth, sim.dt)
    frfs, ltds, roms, sims, missing = {}, {}, [], [], []
    fail = {tuple(f) for f in fail}
    drop = {tuple(d) for d in drop}
    gust_u = {g.name: gust_input(t, g, sim.x0) for g in config.gusts}
    for case_sweep in config.cases:
        name = case_sweep.case.name
        for g in config.gusts:
            if (name, g.name) in drop:
                missing.append(f"ltd {name} {g.name}")
                continue
            t0 = time.perf_counter()
            y = _simulate(truth_dt, gust_u[g.name])
            ltds[(name, g.name)] = LTDRecord(case=name, gust=g.name, t=t, u=gust_u[g.name], cl=y[0], cm=y[1],
                                             seconds=time.perf_counter() - t0)
        for T in case_sweep.T:
            omega_d, omega = sysid.mckelvey_grid(config.M_base, T)
            H_true = continuous_frf(A, B, C, D, omega)
            peak = np.abs(H_true).max(axis=2, keepdims=True)
            H = H_true + noise * peak * (rng.standard_normal(H_true.shape)
                                         + 1j * rng.standard_normal(H_true.shape)) / np.sqrt(2)
            H[:, :, 0] = H[:, :, 0].real
            H[:, :, -1] = H_true[:, :, -1]
            frf = sysid.FrequencyResponse(H[: len(outputs)], omega_d, T, inputs=["gust"], outputs=outputs,
                                          omega=omega, metadata={"case": name, "source": "studies.cli.synthetic"})
            frfs[(name, T)] = FRFRecord(case=name, T=T, M=config.M_base, frf=frf, seconds=0.0, method="synthetic")
            for M in case_sweep.M:
                step = config.M_base // M
                idx = np.arange(0, config.M_base + 1, step)
                data = frf.subsample(M) if M != config.M_base else frf
                for n in case_sweep.orders:
                    for variant in config.methods:
                        ident = dict(case=name, T=T, M=M, order=n, method=variant.name)
                        if (name, M, n, variant.name) in fail:
                            roms.append(RomRecord(status="failed", error="SolverError: synthetic failure", **ident))
                            continue
                        t0 = time.perf_counter()
                        with warnings.catch_warnings():   # synthetic records exercise the report, not the fit
                            warnings.simplefilter("ignore", RuntimeWarning)
                            res = sysid.identify(data, n, **variant.identify_kwargs(data.H))
                        seconds = time.perf_counter() - t0
                        m = res.model
                        frf_rom = res.evaluate(omega_d)
                        dc = np.asarray(res.evaluate(np.array([0.0])))[:, :, 0].real
                        metrics = rom_metrics(frf_rom, frf.H, idx, outputs, dc, res.spectral_radius, seconds)
                        roms.append(RomRecord(status="ok", A=np.asarray(m.A), B=np.asarray(m.B), C=np.asarray(m.C),
                                              D=np.asarray(m.D), hankel_sv=np.asarray(res.hankel_sv),
                                              frf_rom=frf_rom, metrics=metrics, **ident))
                        disc = (sysid.c2d_zoh if sim.discretisation == "zoh" else sysid.c2d_bilinear)
                        rom_dt = disc(sysid.d2c_bilinear(m), sim.dt)
                        for g in config.gusts:
                            if (name, g.name) in drop:
                                continue
                            t0 = time.perf_counter()
                            y = _simulate(rom_dt, gust_u[g.name])
                            s_rom = time.perf_counter() - t0
                            ref = ltds[(name, g.name)]
                            sm = sim_metrics(t, {"Cl": y[0], "Cm": y[1]}, {"Cl": ref.cl, "Cm": ref.cm}, s_rom,
                                             ref.seconds)
                            sims.append(SimRecord(gust=g.name, t=t, cl=y[0], cm=y[1], metrics=sm, **ident))
    return StudyResults(config=config, frf=frfs, ltd=ltds, roms=roms, sims=sims, missing=missing, failed=[],
                        steady={case_sweep.case.name: dict(cl=0.0, cd=0.0, cm=0.0, iterations=0, seconds=0.0)
                                for case_sweep in config.cases})


def main(argv=None) -> int:
    """``python -m studies.cli.synthetic --out DIR``: write the report of the synthetic study to DIR."""
    import argparse

    from ..report.make import make_report

    p = argparse.ArgumentParser(prog="python -m studies.cli.synthetic", description=main.__doc__)
    p.add_argument("--out", default="synthetic-report", help="output folder (default synthetic-report)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quiet", action="store_true")
    args = p.parse_args(argv)
    res = synthetic_results(synthetic_config(args.out), seed=args.seed, fail=[("synth", 16, 10, "plain")])
    page = make_report(res, args.out, progress=not args.quiet)
    print(page)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
