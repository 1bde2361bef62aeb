"""The sub-configurations that key the stored pieces: what enters each key and what does not."""

import pytest

from studies.config.cases import FlowCase, GustCase
from studies.sections.gust_rom.pieces import frf_piece, ltd_piece
from studies.config.schema import CFDOptions, SimulationOptions

CASE = FlowCase("T2", "0010", 0.735)
GUST = GustCase("G3", "one_minus_cosine", 10.0, 1.0)
SIM = SimulationOptions()


@pytest.mark.parametrize("outputs", [("Cl",), ("Cl", "Cm", "Cd")])
def test_the_ltd_key_does_not_depend_on_the_fitted_outputs(outputs):
    # a history always holds Cl, Cm and Cd; the FRF (and everything fitted to it) holds the outputs asked for
    base, other = CFDOptions(), CFDOptions(outputs=outputs)
    assert ltd_piece(CASE, GUST, SIM, other) == ltd_piece(CASE, GUST, SIM, base)
    assert frf_piece(CASE, 11.14, 256, other) != frf_piece(CASE, 11.14, 256, base)


def test_the_ltd_key_follows_what_changes_the_history():
    base = ltd_piece(CASE, GUST, SIM, CFDOptions())
    assert ltd_piece(CASE, GUST, SIM, CFDOptions(gust_method="fvm")) != base
    assert ltd_piece(CASE, GUST, SimulationOptions(scheme="radau5"), CFDOptions()) != base
    assert ltd_piece(CASE, GUST, SimulationOptions(dt=0.01), CFDOptions()) != base
    assert ltd_piece(CASE, GustCase("G4", "one_minus_cosine", 20.0, 1.0), SIM, CFDOptions()) != base
    # the gust's name is a label, not part of what is computed
    assert ltd_piece(CASE, GustCase("other", "one_minus_cosine", 10.0, 1.0), SIM, CFDOptions()) == base
