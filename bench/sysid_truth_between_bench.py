"""Between the samples against the truth, at the order the project recommends: sysid's default fit and vector
fitting side by side on data whose true function is known.

Run: ``python bench/sysid_truth_between_bench.py`` (about a minute on the 2-core machine). Prints one Markdown table.
``--seeds 1,2,3,4,5``: the noisy rows over those noise realisations instead (the 12-state systems drawn with
``10 + seed``), one line per fit and the median ratio per row, of the max errors between the samples and of the
RMS errors over the dense points. ``--estimate``: the default fits of the 12-state rows of seeds 1 - 21 at orders
8, 12 and 16, the estimate of their error between the samples against the truth, and the distribution of that
truth (a few minutes; ``--last-seed 60 --orders 10,12,14,16`` for seeds 1 - 60 at those orders; ``--rows
"sears 1 %"`` or ``--rows "order 4"`` for other noisy rows, by the start of their names).

Data (McKelvey's grid, M = 64 intervals, T = 1, so 65 samples with omega = 0 and inf; the truth on 7999 points of
``omega_d`` strictly between 0 and pi, i.e. about 125 per interval):

- ``sears``: the Sears function with a delay, ``2 pi S(k) exp(-i k)``, ``k = omega / 2`` (an analytic aerofoil
  function with a branch point at zero frequency: no finite order is exact), noise-free;
- ``sears 1 %``: the same with 1 % complex noise;
- ``order 4, 1 %``: a 4-state system (tests/sysid/test_identify.py) with 1 % noise;
- ``12 states, 0.3 %`` and ``12 states, 1 %``: six resonances with damping ratios 2 - 10 %
  (tests/sysid/sysid_synth.py ``noisy_resonant_system``).

For each: the order ``sysid.order_sweep(frf).suggested`` (hold-out rule, passing over orders not pinned down
between the samples), then ``sysid.identify(frf, n, dc_gain="match", stable=True)`` and stable vector fitting
(scikit-rf, ``bench/sysid_peers_bench.py``'s ``run_vf``: best stable fit of the log/linear starts, ``enforce_dc``)
at that order. Columns: max error on the samples and between them against the truth, in % of the data's peak,
and the default's estimate between the samples (``result.between_error``, no truth used).
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "tests" / "sysid"))

import sysid  # noqa: E402
from sysid_synth import noisy_resonant_system  # noqa: E402

WD, W = sysid.mckelvey_grid(64, 1.0)
DENSE = np.linspace(0.0, np.pi, 8001)[1:-1]
W_DENSE = 2.0 * np.tan(DENSE / 2.0)


def _noise(G, level, seed):
    rng = np.random.default_rng(seed)
    G = G + level * np.abs(G).max() * (rng.standard_normal(G.size) + 1j * rng.standard_normal(G.size)) / np.sqrt(2)
    G[0], G[-1] = G[0].real, 0.0
    return G


def sears(omega):
    from aeroelastic.theodorsen import sears_function

    om = np.asarray(omega, dtype=float)
    out = np.zeros(om.shape, dtype=complex)
    fin = np.isfinite(om) & (om > 0)
    out[fin] = 2 * np.pi * sears_function(om[fin] / 2) * np.exp(-1j * om[fin] / 2)
    out[om == 0] = 2 * np.pi
    return out


def order4(omega):
    om = np.asarray(omega, dtype=float)
    s = 1j * np.where(np.isinf(om), 0.0, om)
    return np.where(np.isinf(om), 0.0, 2 * np.pi * (0.13 / (s + 0.26) + 1 / (s + 2)) + 1.8 / (s**2 + 0.6 * s + 9))


def cases(seed=None):
    """The table's data; with ``seed``, the noisy rows only, with that noise seed (and the 12-state systems
    drawn with ``10 + seed``)."""
    if seed is None:
        yield "sears", sears(W), sears(W_DENSE)
    yield "sears 1 %", _noise(sears(W), 0.01, 1 if seed is None else seed), sears(W_DENSE)
    yield "order 4, 1 %", _noise(order4(W), 0.01, 3 if seed is None else seed), order4(W_DENSE)
    for level in (0.003, 0.01):
        kw = {} if seed is None else {"seed": 10 + seed}
        G, truth = noisy_resonant_system(W, W_DENSE, noise=level, **kw)
        yield f"12 states, {100 * level:g} %", G, truth


def compare(G, truth):
    """The default fit at the order the sweep suggests and stable VF at that order, against the truth between
    the samples: ``(frf, order, result, default's max error, VF's max error, VF on the dense points)``, errors
    relative to the data's peak (VF: the same pick as ``run_vf``, on the dense points)."""
    frf = sysid.FrequencyResponse(G, WD, 1.0, outputs=["y"], inputs=["u"])
    peak = np.abs(G).max()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        n = sysid.order_sweep(frf, 20).suggested
        res = sysid.identify(frf, n, dc_gain="match", stable=True)
    H_vf = _vf_at(frf, n, DENSE)
    d = np.abs(res.evaluate(DENSE)[0, 0] - truth).max() / peak
    v = np.abs(H_vf - truth).max() / peak
    return frf, n, res, d, v, H_vf


def rms_between(frf, res, H_vf, truth):
    """RMS error against the truth on the dense points, of the default fit ``res`` and of VF's response ``H_vf``
    there, relative to the data's peak: ``(default, VF)``."""
    peak = np.abs(np.asarray(frf.H)).max()
    rms = lambda H: float(np.sqrt(np.mean(np.abs(H - truth) ** 2)) / peak)  # noqa: E731
    return rms(res.evaluate(DENSE)[0, 0]), rms(H_vf)


def over_seeds(seeds):
    """Median and largest default / VF ratio between the samples over noise realisations, per noisy row: of the
    max error (the table's measure) and of the RMS error over the dense points (the mean-square distance from the
    truth, which the largest error of a noisy fit - one point's - says little about)."""
    ratios, rms_ratios = {}, {}
    for seed in seeds:
        for name, G, truth in cases(seed):
            frf, n, res, d, v, H_vf = compare(G, truth)
            d_rms, v_rms = rms_between(frf, res, H_vf, truth)
            ratios.setdefault(name, []).append(d / v)
            rms_ratios.setdefault(name, []).append(d_rms / v_rms)
            how = "subspace (fallback)" if res.relocation is None else f"{res.relocation.residues} residues"
            print(f"seed {seed} | {name} | order {n} | {how} | default {100 * d:.3g} % | "
                  f"VF {100 * v:.3g} % | ratio {d / v:.2f} | rms ratio {d_rms / v_rms:.2f}", flush=True)
    for name, r in ratios.items():
        q = rms_ratios[name]
        print(f"{name}: median default / VF between the samples {np.median(r):.2f}, largest {max(r):.2f}; "
              f"of the RMS errors: median {np.median(q):.2f}, largest {max(q):.2f}, "
              f"default closer at {sum(x < 1 for x in q)} of {len(q)}")


def estimate_against_truth(seeds, orders=(8, 12, 16), rows=("12 states",)):
    """The estimate of the error between the samples (``result.between_error``, no truth used) against the true
    max error between them, for the default fits of the noisy rows whose names start with one of ``rows`` (the
    12-state ones by default) at ``orders``: one line per realisation, the counts of fits whose estimate is within a
    factor 2 of the truth, more than 2 times above it and more than 2 times below it, and the distribution of the
    truth."""
    log_ratios, truths = [], []
    for seed in seeds:
        for name, G, truth in cases(seed):
            if not name.startswith(tuple(rows)):
                continue
            frf = sysid.FrequencyResponse(G, WD, 1.0, outputs=["y"], inputs=["u"])
            peak = np.abs(G).max()
            cells = []
            for n in orders:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    res = sysid.identify(frf, n, dc_gain="match", stable=True)
                true = np.abs(res.evaluate(DENSE)[0, 0] - truth).max() / peak
                log_ratios.append(np.log(max(res.between_error, 1e-12) / true))
                truths.append(true)
                cells.append(f"order {n}: estimate {res.between_error:.4f}, truth {true:.4f}")
            print(f"seed {seed} | {name} | " + " | ".join(cells), flush=True)
    r = np.array(log_ratios)
    print(f"{r.size} fits: estimate within a factor 2 of the truth at {int(np.sum(np.abs(r) < np.log(2)))}, more than "
          f"2 times above at {int(np.sum(r > np.log(2)))}, more than 2 times below at {int(np.sum(r < -np.log(2)))}; "
          f"geometric mean estimate / truth {np.exp(r.mean()):.2f}")
    t = np.array(truths)
    print(f"true max error between the samples: median {np.median(t):.4f}, geometric mean {np.exp(np.log(t).mean()):.4f}"
          f", above 5 % of the peak at {int(np.sum(t > 0.05))}, above 10 % at {int(np.sum(t > 0.1))}, above 20 % at "
          f"{int(np.sum(t > 0.2))} of {t.size} fits")


def main():
    from sysid_peers_bench import run_vf

    if "--seeds" in sys.argv:
        over_seeds([int(x) for x in sys.argv[sys.argv.index("--seeds") + 1].split(",")])
        return
    if "--estimate" in sys.argv:
        last = int(sys.argv[sys.argv.index("--last-seed") + 1]) if "--last-seed" in sys.argv else 21
        orders = ((8, 12, 16) if "--orders" not in sys.argv
                  else tuple(int(x) for x in sys.argv[sys.argv.index("--orders") + 1].split(",")))
        rows = (("12 states",) if "--rows" not in sys.argv
                else tuple(sys.argv[sys.argv.index("--rows") + 1].split(",")))
        estimate_against_truth(range(1, last + 1), orders, rows)
        return

    rows = ["| data | order (sweep) | default: samples | default: between (truth) | default: estimate | "
            "VF: samples | VF: between (truth) | default / VF between |",
            "| --- | ---: | --- | --- | --- | --- | --- | --- |"]
    for name, G, truth in cases():
        frf, n, res, d_btw, v_btw, _ = compare(G, truth)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            vf = run_vf(frf, n)
        d_on = res.max_error
        v_on = np.abs(vf["H"] - frf.H).max() / np.abs(G).max()
        rows.append(f"| {name} | {n} | {100 * d_on:.3g} | {100 * d_btw:.3g} | {100 * res.between_error:.3g} | "
                    f"{100 * v_on:.3g} | {100 * v_btw:.3g} | {d_btw / v_btw:.2f} |")
        print(rows[-1], flush=True)
    print("\n".join(rows))


def _vf_at(frf, n, omega_d):
    """Stable VF (best of the log / linear starts on the samples, as ``run_vf``) evaluated at ``omega_d``."""
    import skrf
    from skrf.vectorFitting import VectorFitting

    fin = np.isfinite(frf.omega)
    f = frf.omega[fin] / (2 * np.pi)
    H = np.asarray(frf.H)[0, 0]
    peak = np.abs(H).max()
    nw = skrf.Network(frequency=skrf.Frequency.from_f(f, unit="hz"), s=(H[fin] / peak).reshape(-1, 1, 1))
    best = None
    for spacing in ("log", "lin"):
        vf = VectorFitting(nw)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                vf.vector_fit(n_poles_real=n % 2, n_poles_cmplx=n // 2, init_pole_spacing=spacing,
                              fit_constant=True, fit_proportional=False, enforce_dc=True)
        except Exception:
            continue
        if not np.all(vf.poles.real < 0):
            continue
        e = np.abs(vf.get_model_response(0, 0, f) * peak - H[fin]).max()
        if best is None or e < best[0]:
            best = (e, vf)
    wd = np.asarray(omega_d)
    return best[1].get_model_response(0, 0, (2.0 / frf.T) * np.tan(wd / 2) / (2 * np.pi)) * peak


if __name__ == "__main__":
    main()
