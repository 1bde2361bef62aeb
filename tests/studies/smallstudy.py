"""The small synthetic study of the report, prose-template and write-safety tests: one NACA0012 case whose store
:func:`studies.cli.synthetic.synthetic_results` fills without CFD (known systems), two orders, two grids, the
paper's identification and the stable DC-exact one."""

from pathlib import Path

from studies.cli.synthetic import synthetic_results
from studies.config import loads_study

_TEXT = """
name = "small"
{description}output = "{out}"
cases = [{{name = "synth", naca = "0012", mach = 0.5}}]
gusts = [{gusts}]
[sweep]
orders = [2, 6]
T = ["70/(2*pi)"]
M_base = 32
M = [32, 16]
[methods.plain]
[methods.dc_stable]
dc_gain = "match"
stable = true
[simulation]
dt = 0.1
t_end = 20.0
"""


def small_study_text(out, gusts=("G3", "G4"), description=None) -> str:
    """The study file's text, writing to ``out``, with ``gusts`` and an optional ``description``."""
    return _TEXT.format(out=Path(out).as_posix(), gusts=", ".join(f'"{g}"' for g in gusts),
                        description="" if description is None else f'description = "{description}"\n')


def small_results(out, gusts=("G3", "G4"), **synthetic):
    """The study's results in a store under ``out`` (``synthetic``: ``fail``/``drop`` of ``synthetic_results``)."""
    return synthetic_results(loads_study(small_study_text(out, gusts), base_dir=out), **synthetic)
