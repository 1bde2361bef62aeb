"""cfd.preset_grid: the paper grid and the coarse grid by name; unknown names are refused with the known ones."""

import pytest

import cfd


@pytest.mark.parametrize("name, ni, nj, wall", [("coarse", 65, 17, 48)])
def test_preset_grid_sizes(name, ni, nj, wall):
    grid = cfd.preset_grid(cfd.naca("0012"), name)
    assert grid.x.shape == (ni, nj)
    assert cfd.GRID_PRESETS[name]["n_surface"] == wall


def test_paper_preset_is_c_grid_default():
    import inspect

    defaults = {k: v.default for k, v in inspect.signature(cfd.c_grid).parameters.items()}
    assert all(defaults[k] == v for k, v in cfd.GRID_PRESETS["paper"].items())


@pytest.mark.parametrize("name", ["fine", "", None, 3])
def test_unknown_preset_is_refused(name):
    with pytest.raises(cfd.MeshError, match=r"unknown grid preset .*'paper', 'coarse'"):
        cfd.preset_grid(cfd.naca("0012"), name)


def test_presets_are_read_only():
    with pytest.raises(TypeError):
        cfd.GRID_PRESETS["coarse"]["nj"] = 9
