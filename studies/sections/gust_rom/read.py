"""What the store holds of the gust-ROM section (steady flows, FRFs, LTD histories, ROMs, ROM simulations), for
:func:`studies.store.results.load_results`; computes nothing.

A missing steady flow leaves its case's pieces missing; a failed one marks its FRFs and LTD histories not
computable (they are not listed as missing) and its ROMs failed with that reason; a failed FRF marks the ROMs
fitted to it failed; a failed LTD history leaves the ROM simulations of that gust out of ``missing``.
"""

from __future__ import annotations

from sysid import FrequencyResponse

from ...config.schema import StudyConfig, SweepPoint
from ...store.entries import is_failed
from ...store.results import FRFRecord, LTDRecord, RomRecord, SimRecord
from ..protocol import SectionRead
from .pieces import frf_piece, ltd_piece, rom_piece, sim_piece, steady_piece

__all__ = ["read_gust_rom"]


def _fmt_T(T: float) -> str:
    return f"T={T:.6g}"


def read_gust_rom(config: StudyConfig, store) -> SectionRead:
    """The gust-ROM pieces of a study in ``store``.

    Returns
    -------
    SectionRead
        ``fields``: ``frf``, ``ltd``, ``roms``, ``sims``, ``steady`` of :class:`studies.store.results.StudyResults`;
        ``unavailable``: the cases whose steady flow failed.
    """
    outputs = list(config.cfd.outputs)
    frfs: dict = {}
    ltds: dict = {}
    roms: list = []
    sims: list = []
    missing: list = []
    failed: list = []
    steady: dict = {}
    case_fail: dict = {}   # case name -> reason (steady failed or missing)
    frf_fail: dict = {}    # (case, T) -> reason

    for case_sweep in config.cases:
        c = case_sweep.case
        e = store.get("steady", steady_piece(c))
        if e is None:
            missing.append(f"steady {c.name}")
        elif is_failed(e):
            reason = f"steady flow of {c.name} failed: {e.metadata.get('error')}"
            failed.append(reason)
            case_fail[c.name] = reason
        else:
            steady[c.name] = {k: e.metadata.get(k) for k in ("cl", "cd", "cm", "iterations", "converged", "seconds")}
        for T in case_sweep.T:
            e = store.get("frf", frf_piece(c, T, config.M_base, config.cfd))
            if e is None:
                if c.name not in case_fail:  # without a steady flow there is nothing to compute
                    missing.append(f"frf {c.name} {_fmt_T(T)}")
                continue
            if is_failed(e):
                reason = f"frequency response of {c.name} at {_fmt_T(T)} failed: {e.metadata.get('error')}"
                failed.append(reason)
                frf_fail[(c.name, T)] = reason
                continue
            md = e.metadata
            frf = FrequencyResponse(e["H"], e["omega_d"], T, inputs=md.get("inputs", ["gust"]),
                                    outputs=md.get("outputs", outputs), omega=e["omega"],
                                    metadata={**md.get("lfd", {}), "case": c.name, "method": md.get("method", "auto")})
            frfs[(c.name, T)] = FRFRecord(case=c.name, T=T, M=config.M_base, frf=frf,
                                          seconds=float(md.get("seconds", float("nan"))),
                                          method=str(md.get("method", "auto")), lfd=dict(md.get("lfd", {})))
        for g in config.gusts:
            e = store.get("ltd", ltd_piece(c, g, config.simulation, config.cfd))
            if e is None:
                if c.name not in case_fail:
                    missing.append(f"ltd {c.name} {g.name}")
            elif is_failed(e):
                failed.append(f"LTD response of {c.name} to {g.name} failed: {e.metadata.get('error')}")
            else:
                ltds[(c.name, g.name)] = LTDRecord(case=c.name, gust=g.name, t=e["t"], u=e["u"], cl=e["cl"],
                                                   cm=e["cm"], seconds=float(e.metadata.get("seconds", float("nan"))))

    for pt in config.points():
        _read_point(store, config, pt, frfs, ltds, case_fail, frf_fail, roms, sims, missing, failed)

    return SectionRead(fields=dict(frf=frfs, ltd=ltds, roms=roms, sims=sims, steady=steady), missing=missing,
                       failed=failed, unavailable=frozenset(case_fail))


def _read_point(store, config: StudyConfig, pt: SweepPoint, frfs, ltds, case_fail, frf_fail, roms, sims, missing,
                failed) -> None:
    c = pt.case
    ident = dict(case=c.name, T=pt.T, M=pt.M, order=pt.order, method=pt.method.name)
    label = f"{c.name} {_fmt_T(pt.T)} M={pt.M} N_r={pt.order} {pt.method.name}"
    e = store.get("rom", rom_piece(pt, config.M_base, config.cfd))
    if e is None:
        reason = frf_fail.get((c.name, pt.T)) or (case_fail.get(c.name) if (c.name, pt.T) not in frfs else None)
        if reason is not None:
            roms.append(RomRecord(status="failed", error=reason, **ident))
        else:
            missing.append(f"rom {label}")
        return
    if is_failed(e):
        roms.append(RomRecord(status="failed", error=str(e.metadata.get("error")), **ident))
        return
    roms.append(RomRecord(status="ok", error=None, A=e["A"], B=e["B"], C=e["C"], D=e["D"], hankel_sv=e["hankel_sv"],
                          frf_rom=e["frf_rom"], metrics=dict(e.metadata.get("metrics", {})), **ident))
    for g in config.gusts:
        s = store.get("sim", sim_piece(pt, g, config.M_base, config.simulation, config.cfd))
        if s is None:
            if (c.name, g.name) in ltds or not any(f.startswith(f"LTD response of {c.name} to {g.name} ")
                                                   for f in failed):
                missing.append(f"sim {label} {g.name}")
            continue
        if is_failed(s):
            failed.append(f"ROM response of {label} to {g.name} failed: {s.metadata.get('error')}")
            continue
        sims.append(SimRecord(gust=g.name, t=s["t"], cl=s["cl"], cm=s["cm"], metrics=dict(s.metadata.get("metrics", {})),
                              **ident))
