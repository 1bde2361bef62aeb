"""The names that moved out of the flat studies package still answer (the old module paths themselves, and that
no project code imports one: tests/test_legacy_paths.py)."""

import importlib

import pytest


@pytest.mark.parametrize("module, name", [("studies.config", "frf_piece"), ("studies.store.results", "sim_payload")])
def test_moved_names_warn(module, name):
    with pytest.warns(DeprecationWarning, match=f"moved to studies.sections.gust_rom.pieces.{name}"):
        value = getattr(importlib.import_module(module), name)
    assert value is getattr(importlib.import_module("studies.sections.gust_rom.pieces"), name)


def test_packages_keep_their_names():
    import studies.cli
    import studies.config
    import studies.report

    assert callable(studies.cli.main) and callable(studies.config.load_study) and callable(studies.report.make_report)
