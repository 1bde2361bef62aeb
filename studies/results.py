"""Results of a study read back from the store (contract between studies.runner and studies.report).

CONTRACT (to implement here; the text below is the agreed interface):

## Shared contract between the runner (helper A) and the report (helper B)

`studies/results.py` (owned by helper A, committed FIRST, within ~20 minutes, before the runner itself) defines
what a finished (or partly finished) study looks like when read back from the results store. Pure data, frozen
dataclasses, NumPy arrays, no CFD objects:

```python
@dataclass(frozen=True)
class FRFRecord:          # the LFD gust frequency response of one case at one T (M_base + 1 points)
    case: str; T: float; M: int
    frf: sysid.FrequencyResponse     # outputs ("Cl", "Cm"), input "gust", omega (continuous, U/c units), omega_d, T
    seconds: float                   # compute time
    method: str                      # "direct" | "fast"
@dataclass(frozen=True)
class LTDRecord:          # the LTD reference response of one case to one gust
    case: str; gust: str             # "T2", "G3"
    t: np.ndarray; u: np.ndarray; cl: np.ndarray; cm: np.ndarray   # shape (n+1,), convective time, per the gust's real amplitude
    seconds: float
@dataclass(frozen=True)
class RomRecord:          # one sweep point (case, T, M, order, method)
    case: str; T: float; M: int; order: int; method: str   # method = the study's method-variant name, e.g. "dc_stable"
    status: str                      # "ok" | "failed"
    error: str | None                # "ExceptionType: message" when failed
    A: np.ndarray | None; B; C; D    # discrete ROM at sampling period T (None when failed)
    hankel_sv: np.ndarray | None     # (q,) Hankel singular values from the subspace step
    frf_rom: np.ndarray | None       # (p, 1, M_base + 1) ROM evaluated at the FRFRecord's omega_d points
    metrics: dict                    # frf_max_err_Cl, frf_rms_err_Cl, frf_max_err_Cm, frf_rms_err_Cm (relative, sysid.metrics),
                                     # dc_err_Cl, dc_err_Cm (absolute), spectral_radius, stable (bool), seconds
@dataclass(frozen=True)
class SimRecord:          # ROM response to one gust vs the LTD one
    case: str; T: float; M: int; order: int; method: str; gust: str
    t: np.ndarray; cl: np.ndarray; cm: np.ndarray      # ROM on the LTD time grid
    metrics: dict    # peak_err_Cl, peak_err_Cm (relative to |LTD peak|), t_peak_err_Cl, t_peak_err_Cm (convective time),
                     # rms_err_Cl, rms_err_Cm (relative to LTD RMS), seconds_rom, seconds_ltd
@dataclass(frozen=True)
class StudyResults:
    config: StudyConfig
    frf: dict[tuple[str, float], FRFRecord]            # (case, T)
    ltd: dict[tuple[str, str], LTDRecord]              # (case, gust)
    roms: list[RomRecord]
    sims: list[SimRecord]
    missing: list[str]                                 # human-readable list of pieces not in the store yet
    def table(self, kind: str = "rom" | "sim") -> list[dict]   # one flat dict per record: keys above + metrics
```

`studies.load_results(study_or_path) -> StudyResults` reads the store only (never computes). `studies.run_study(study_or_path, *,
scheduler=None, workers=None, progress=True) -> StudyResults` computes what is missing, then returns load_results.
`studies.report.make_report(study_or_path, out_dir=None) -> pathlib.Path` (helper B) builds everything from
load_results only; `studies/commands.py` already hands `lfdrom run` / `lfdrom report` over to
`studies.runner.run_study` / `studies.report.make_report` (read it; keep its behaviour and exit codes).
If a field turns out to be wrong while building, helper A may change results.py, and must say so in its commit
message; helper B reads results.py from git (git log -p studies/results.py) before relying on it.
"""
