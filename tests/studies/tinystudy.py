"""The tiny study shared by the runner and reliability tests (its fixture ``computed`` is in conftest.py)."""

import shutil

# T2 (NACA0010, M0.735) on a 61 x 16 grid, far field 10 chords (3600 unknowns): CFD in seconds.
# G4 (1-cosine, 10 chords) has its energy below omega ~ 1.3, inside the band of McKelvey's M = 16 grid at
# T = 70 / (2 pi) (omega_k = (2/T) tan(pi k / 32) <= 1.8 for k < 15), so the ROM is compared with the LTD
# response where it was identified.
STUDY = """
name = "tiny"
output = "out"
cases = ["T2"]
gusts = ["G4"]
[grid]
ni = 61
nj = 16
n_surface = 40
farfield = 10.0
[sweep]
orders = [2, 4]
T = ["70/(2*pi)"]
M_base = 16
M = [16, 8]
[methods.plain]
[methods.dc_stable]
dc_gain = "match"
stable = true
margin = 1e-3
[simulation]
dt = 0.1
t_end = 16.0
x0 = -2.0
"""

N_POINTS = 8  # 2 M x 2 orders x 2 methods


def copy_study(config, tmp_path, drop=()):
    """The computed study on a copy of its store, without the pieces in ``drop``."""
    from dataclasses import replace

    store = tmp_path / "store"
    shutil.copytree(config.store_dir, store)
    for piece in drop:
        shutil.rmtree(store / piece, ignore_errors=True)
    return replace(config, store_dir=store, output_dir=tmp_path / "out")
