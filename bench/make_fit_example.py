"""Write docs/data/fit-example.csv: the worked example of ``lfdrom fit`` (docs/fit.md).

An analytic gust response with known poles, on reduced frequencies that no McKelvey grid would give:

- lift from Kuessner's function in R. T. Jones' approximation, psi(tau) = 1 - 0.5 exp(-0.13 tau) - 0.5 exp(-tau)
  (tau = 2 s semichords; s = t U / c convective time), so per radian of gust angle

      Cl(s) = 2 pi [0.5 * 0.26 / (s + 0.26) + 0.5 * 2 / (s + 2)]          (Laplace variable s in U/c)

  with DC gain 2 pi (quasi-steady thin-aerofoil lift) and zero feedthrough;
- a lightly damped mode (omega_n = 3, zeta = 0.1, i.e. k = 1.5) with zero DC gain adds 3 % of structure:
  + 2 pi * 0.03 * (2 zeta omega_n s) / (s^2 + 2 zeta omega_n s + omega_n^2);
- Cm about the quarter chord: the same four poles with other residues,
  Cm(s) = 2 pi [-0.02 * 0.26 / (s + 0.26) + 0.03 * 2 / (s + 2)] - 2 pi * 0.01 * (2 zeta omega_n s) / (...).

True order 4: poles -0.26, -2 and -0.3 +- 2.985i (U/c). Frequencies: k = 0, 60 values log-spaced from 0.01 to 5,
and omega = inf (k = inf, value 0: the feedthrough). Run: .venv/bin/python bench/make_fit_example.py
"""

from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "docs" / "data" / "fit-example.csv"
WN, ZETA = 3.0, 0.1
POLES = np.array([-0.26, -2.0, -ZETA * WN + 1j * WN * np.sqrt(1 - ZETA**2), -ZETA * WN - 1j * WN * np.sqrt(1 - ZETA**2)])


def response(omega):
    """``(Cl, Cm)`` at angular frequencies ``omega`` (U/c; inf allowed), complex arrays."""
    w = np.asarray(omega, dtype=float)
    fin = np.isfinite(w)
    s = 1j * np.where(fin, w, 0.0)
    mode = 2 * ZETA * WN * s / (s**2 + 2 * ZETA * WN * s + WN**2)
    cl = 2 * np.pi * (0.5 * 0.26 / (s + 0.26) + 0.5 * 2 / (s + 2) + 0.03 * mode)
    cm = 2 * np.pi * (-0.02 * 0.26 / (s + 0.26) + 0.03 * 2 / (s + 2) - 0.01 * mode)
    return np.where(fin, cl, 0.0), np.where(fin, cm, 0.0)


def main(path=OUT):
    k = np.concatenate([[0.0], np.logspace(-2, np.log10(5.0), 60), [np.inf]])
    cl, cm = response(2 * k)
    lines = ["# lfdrom fit worked example (bench/make_fit_example.py): Kuessner lift + a 3 % mode at k = 1.5",
             "# frequency: k", "# input: gust", "k,Cl_re,Cl_im,Cm_re,Cm_im"]
    for row in zip(k, cl.real, cl.imag, cm.real, cm.imag):
        lines.append(",".join("inf" if np.isinf(v) else f"{v:.12g}" for v in row))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


if __name__ == "__main__":
    print(f"wrote {main()}")
