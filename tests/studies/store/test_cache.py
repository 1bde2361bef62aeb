"""The results store: round trip, keys, atomic writes under crashes, corruption, provenance, concurrency, ROM files."""

import datetime
import json
import logging
import multiprocessing
import os
import sys

import control
import numpy as np
import pytest
import scipy.io

from studies.store import provenance as prov
from studies.store.cache import (
    CacheError,
    ResultStore,
    StoreReadError,
    export_rom_mat,
    export_rom_npz,
    load_rom_npz,
)

CODE = {"lfdrom": "test", "sources": "fixed"}
CONFIG = {"steady": {"naca": "0010", "mach": 0.735}, "T": 11.1408460164, "M": 256}

_ctx = multiprocessing.get_context("fork") if "fork" in multiprocessing.get_all_start_methods() else None
needs_fork = pytest.mark.skipif(_ctx is None, reason="needs the fork start method")


def arrays():
    return {"H": (np.arange(6.0) + 1j).reshape(2, 1, 3), "omega": np.array([0.0, 1.0, np.inf])}


def visible(root):
    """Committed files (not hidden temporaries)."""
    return sorted(p.name for p in root.rglob("*") if p.is_file() and not p.name.startswith("."))


def test_round_trip_and_hit(tmp_path):
    store = ResultStore(tmp_path, code=CODE)
    calls = []

    def compute():
        calls.append(1)
        return arrays(), {"n": np.int64(3), "err": np.float64(0.5), "names": ("Cl", "Cm")}

    e1 = store.get_or_compute("frf", CONFIG, compute)
    e2 = store.get_or_compute("frf", json.loads(json.dumps(CONFIG)), compute)
    assert (e1.hit, e2.hit, len(calls)) == (False, True, 1)
    for name, a in arrays().items():
        np.testing.assert_array_equal(e2[name], a)
        assert e2[name].dtype == a.dtype
    assert e2.metadata == {"n": 3, "err": 0.5, "names": ["Cl", "Cm"]}
    assert e2.key == e1.key and e2.path.exists() and e2.config == e1.config
    assert e2.provenance["compute_s"] >= 0
    assert ("frf", e1.key) in list(store.keys()) and ("frf", CONFIG) in store


def test_keys(tmp_path):
    store = ResultStore(tmp_path, code=CODE)
    k = store.key("frf", CONFIG)
    assert k == store.key("frf", {"M": 256, "T": 11.14084601640000001, "steady": {"mach": 0.735, "naca": "0010"}})
    assert k != store.key("rom", CONFIG)
    assert k != store.key("frf", {**CONFIG, "M": 128})
    assert k != ResultStore(tmp_path, code={**CODE, "sources": "edited"}).key("frf", CONFIG)
    # the default code version: package version and the sources of the piece's packages
    default = ResultStore(tmp_path)
    assert default.code_version("rom")["packages"] == [
        "cfd", "studies.config.entries", "studies.config.numbers", "studies.config.reader", "studies.config.schema",
        "studies.config.study", "studies.sections.gust_rom.pieces", "studies.sections.gust_rom.tasks", "sysid"]
    assert default.code_version("frf")["packages"] == ["cfd"]
    with pytest.raises(CacheError, match="piece"):
        store.key("../x", CONFIG)


def test_source_hash_follows_the_sources(tmp_path, monkeypatch):
    pkg = tmp_path / "lfdrom_tmp_pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("x = 1\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    h1 = prov.source_hash(("lfdrom_tmp_pkg",))
    (pkg / "__init__.py").write_text("x = 2\n")
    prov.source_hash.cache_clear()
    assert prov.source_hash(("lfdrom_tmp_pkg",)) != h1
    prov.source_hash.cache_clear()


def test_provenance_contents(tmp_path):
    e = ResultStore(tmp_path).put("rom", CONFIG, arrays())
    p = e.provenance
    assert p["config"] == json.loads(json.dumps(CONFIG)) and p["piece"] == "rom"
    assert set(p["packages"]) >= {"numpy", "scipy", "cvxpy", "clarabel", "control", "lfdrom"}
    assert p["packages"]["numpy"] == np.__version__
    assert p["python"] == sys.version.split()[0]
    assert p["hostname"] and p["pid"] == os.getpid()
    assert datetime.datetime.fromisoformat(p["timestamp"]).tzinfo is not None
    assert p["code"]["sources"] and len(p["code"]["sources"]) == 64
    if p["git"] is not None:
        assert len(p["git"]["commit"]) == 40 and isinstance(p["git"]["dirty"], bool)
    # the stored JSON holds it too
    body = json.loads(e.path.read_text())["body"]
    assert body["provenance"]["packages"] == p["packages"]


@pytest.mark.parametrize("damage", ["truncate_npz", "flip_npz", "delete_npz", "truncate_json", "edit_json",
                                    "garbage_json"])
def test_corruption_is_detected_and_recomputed(tmp_path, caplog, damage):
    store = ResultStore(tmp_path, code=CODE)
    e = store.put("frf", CONFIG, arrays())
    npz = next(tmp_path.rglob("*.npz"))
    if damage == "truncate_npz":
        npz.write_bytes(npz.read_bytes()[:50])
    elif damage == "flip_npz":
        b = bytearray(npz.read_bytes())
        b[len(b) // 2] ^= 0xFF
        npz.write_bytes(bytes(b))
    elif damage == "delete_npz":
        npz.unlink()
    elif damage == "truncate_json":
        e.path.write_bytes(e.path.read_bytes()[:100])
    elif damage == "edit_json":
        e.path.write_text(e.path.read_text().replace('"M": 256', '"M": 257'))
    else:
        e.path.write_bytes(b"\x00\xff not json")
    with caplog.at_level(logging.WARNING, logger="studies.store.cache"):
        again = store.get_or_compute("frf", CONFIG, lambda: {"H": np.ones(2)})
    assert not again.hit and np.all(again["H"] == 1.0)
    assert any("corrupted entry" in r.getMessage() for r in caplog.records)
    assert store.get_or_compute("frf", CONFIG, lambda: 1 / 0).hit


def _crash_on(step, root, value):
    """Child process: write an entry and die (os._exit) at ``step`` of the atomic write."""
    import studies.store.files as files  # the store's atomic writer

    real_replace, real_fsync = os.replace, os.fsync
    calls = {"fsync": 0}

    def replace(src, dst, *a, **k):
        if step == "json_rename" and str(dst).endswith(".json"):
            os._exit(3)
        return real_replace(src, dst, *a, **k)

    def fsync(fd):
        calls["fsync"] += 1
        if step == "npz_write" and calls["fsync"] == 1:
            os._exit(3)
        return real_fsync(fd)

    files.os.replace = replace
    files.os.fsync = fsync
    ResultStore(root, code=CODE).put("frf", CONFIG, {"H": np.full(1000, value)})
    os._exit(0)


@needs_fork
@pytest.mark.parametrize("step", ["npz_write", "json_rename"])
def test_crash_mid_write_leaves_no_visible_entry(tmp_path, step):
    store = ResultStore(tmp_path, code=CODE)
    p = _ctx.Process(target=_crash_on, args=(step, tmp_path, 1.0))
    p.start()
    p.join(30)
    assert p.exitcode == 3
    assert store.get("frf", CONFIG) is None and list(store.keys()) == []
    assert not any(n.endswith(".json") for n in visible(tmp_path))
    assert store.clean(max_age=0.0) >= 1  # the temporary file or the unreferenced npz
    assert visible(tmp_path) == []
    assert not store.get_or_compute("frf", CONFIG, lambda: {"H": np.zeros(3)}).hit


@needs_fork
def test_crash_while_replacing_keeps_the_old_entry(tmp_path):
    store = ResultStore(tmp_path, code=CODE)
    store.put("frf", CONFIG, {"H": np.full(1000, 7.0)})
    p = _ctx.Process(target=_crash_on, args=("json_rename", tmp_path, 8.0))
    p.start()
    p.join(30)
    assert p.exitcode == 3
    e = store.get("frf", CONFIG)
    assert e is not None and np.all(e["H"] == 7.0)


def _writer(root, n, seed):
    store = ResultStore(root, code=CODE)
    for i in range(n):
        store.put("rom", CONFIG, {"A": np.eye(4) * 2.0, "i": np.array(seed * 1000 + i)}, {"writer": seed})
    os._exit(0)


@needs_fork
def test_concurrent_writers_same_key(tmp_path, caplog):
    store = ResultStore(tmp_path, code=CODE)
    procs = [_ctx.Process(target=_writer, args=(tmp_path, 25, s)) for s in (1, 2)]
    for p in procs:
        p.start()
    with caplog.at_level(logging.WARNING, logger="studies.store.cache"):
        while any(p.is_alive() for p in procs):
            e = store.get("rom", CONFIG)  # a reader alongside: never a torn entry
            if e is not None:
                np.testing.assert_array_equal(e["A"], np.eye(4) * 2.0)
                assert e.metadata["writer"] in (1, 2)
        for p in procs:
            p.join(30)
            assert p.exitcode == 0
    assert not any("corrupted" in r.getMessage() for r in caplog.records)
    e = store.get("rom", CONFIG)
    assert e is not None and np.array_equal(e["A"], np.eye(4) * 2.0) and len(list(store.keys())) == 1
    store.clean(max_age=0.0)
    assert len(list(tmp_path.rglob("*.npz"))) == 1  # orphans of the losing writes are gone
    assert store.get("rom", CONFIG) is not None


def test_bad_inputs(tmp_path):
    store = ResultStore(tmp_path, code=CODE)
    with pytest.raises(CacheError, match="dtype object"):
        store.put("frf", CONFIG, {"x": np.array([{}, 1], dtype=object)})
    with pytest.raises(CacheError, match="must return"):
        store.get_or_compute("frf", CONFIG, lambda: [1, 2])
    with pytest.raises(CacheError, match="JSON"):
        store.put("frf", CONFIG, {"x": np.ones(1)}, {"bad": object()})
    assert store.delete("frf", CONFIG) is False
    store.put("frf", CONFIG, {"x": np.ones(1)})
    assert store.delete("frf", CONFIG) is True and store.get("frf", CONFIG) is None


def _model(dt):
    A = np.array([[0.5, 0.1], [0.0, -0.3]])
    if not dt:
        A = A - np.eye(2)
    return control.ss(A, [[1.0], [0.5]], [[1.0, 2.0], [0.0, -1.0]], [[0.0], [0.1]], dt=dt,
                      inputs=["gust"], outputs=["Cl", "Cm"])


@pytest.mark.parametrize("dt", [11.1408460164, 0])
def test_rom_mat_round_trip(tmp_path, dt):
    m = _model(dt)
    path = export_rom_mat(tmp_path / "rom.mat", m, {"case": "T2", "order": 2, "max_err": np.float64(1e-3)})
    r = scipy.io.loadmat(path)
    for name in "ABCD":
        np.testing.assert_array_equal(r[name], getattr(m, name))
    assert float(r["T"].squeeze()) == (dt or 0.0)
    assert [str(x[0][0]) for x in r["InputName"]] == ["gust"]
    assert [str(x[0][0]) for x in r["OutputName"]] == ["Cl", "Cm"]
    assert json.loads(str(r["metadata"][0])) == {"case": "T2", "order": 2, "max_err": 1e-3}
    assert [p.name for p in tmp_path.iterdir()] == ["rom.mat"]  # no temporary left


@pytest.mark.parametrize("dt", [0.25, 0])
def test_rom_npz_round_trip(tmp_path, dt):
    m = _model(dt)
    back, meta = load_rom_npz(export_rom_npz(tmp_path / "rom.npz", m, {"case": "T2"}))
    for name in "ABCD":
        np.testing.assert_array_equal(getattr(back, name), getattr(m, name))
    assert back.dt == m.dt and back.input_labels == ["gust"] and back.output_labels == ["Cl", "Cm"]
    assert meta == {"case": "T2"}


def test_an_entry_of_another_payload_layout_is_recomputed(tmp_path, caplog):
    """A valid entry whose arrays are not the piece's layout (written by another version under a key that hashes
    only the computing code) would fail every reader with a KeyError: it is corrupt, deleted and recomputed; a
    recorded failure (no arrays) is not."""
    required = {"frf": ("H", "omega")}
    store = ResultStore(tmp_path, code=CODE, required=required)
    ResultStore(tmp_path, code=CODE).put("frf", CONFIG, {"H": np.ones(2)})  # no omega: another layout
    with caplog.at_level(logging.WARNING, logger="studies.store.cache"):
        assert store.get("frf", CONFIG) is None
    assert any("arrays omega are missing" in r.getMessage() for r in caplog.records)
    store.put("frf", CONFIG, {}, {"status": "failed", "error": "diverged"})
    assert store.get("frf", CONFIG).metadata["status"] == "failed"


def test_an_unreadable_entry_is_a_store_read_error_not_a_write_failure(tmp_path):
    # a folder where the entry's file should be: not corruption (nothing is deleted), and not a write failure
    store = ResultStore(tmp_path, code=CODE)
    e = store.put("frf", CONFIG, arrays())
    e.path.unlink()
    e.path.mkdir()
    with pytest.raises(StoreReadError, match="the results store cannot be read at .*IsADirectoryError"):
        store.get("frf", CONFIG)
    assert e.path.is_dir()
    # the same for its array file
    e2 = store.put("rom", CONFIG, arrays())
    npz = e2.path.with_name(json.loads(e2.path.read_text())["body"]["npz"]["file"])
    npz.unlink()
    npz.mkdir()
    with pytest.raises(StoreReadError, match=r"cannot be read at .*\.npz"):
        store.get("rom", CONFIG)
