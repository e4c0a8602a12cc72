"""Studies over every pulse family (Setting(pulse=...)), held to an independent simulation of the bare block."""

from __future__ import annotations

import numpy as np
import pytest

import rocking
from rocking.model.params import ParameterError
from rocking.study.config import Grid, Setting, Tuning
from rocking.study.overturning_map import overturning_map
from rocking.study.spectrum import envelope, minimum_overturning_spectrum
from rocking.study.tiles import Execution
from rocking.study.vocabulary import BRACKETED

SERIAL = Execution(workers=1, progress=False)

#: The bare symmetric block of alpha = 0.25, p = 2 rad/s: the smallest a_p / (g tan alpha), on a grid of 0.01, that
#: overturns it, from a separate implementation (nonlinear equations of motion, Housner's restitution
#: 1 - 1.5 sin^2 alpha, scipy.integrate.solve_ivp with events), written for this check apart from this code base.
#: No published table of these values was found; they are an independent check, not a literature value.
INDEPENDENT = {"sine": {2.0: 1.23, 3.0: 1.41, 4.0: 1.79, 6.0: 4.64}, "cosine": {2.0: 1.41, 3.0: 1.86, 4.0: 3.43}}


@pytest.mark.parametrize("pulse", ["sine", "cosine"])
def test_bare_beta_min_agrees_with_an_independent_simulation(pulse, tmp_path):
    block = rocking.Block.from_nondim(p=2.0, alpha=0.25, M=1000.0)
    Omega = sorted(INDEPENDENT[pulse])
    study = minimum_overturning_spectrum(
        Setting(block, pulse=pulse),
        Tuning(0.05),
        Grid("Omega", Omega[0], Omega[-1], int(Omega[-1] - Omega[0]) + 1),
        Grid("beta", 0.5, 8.0, 151),
        SERIAL,
        tol=1e-4,
        runs=tmp_path,
    )
    bare = envelope(study.data).sel(part="bare")
    for i, Om in enumerate(bare["Omega"].values):
        if Om in INDEPENDENT[pulse]:
            assert bare["flag"].values[i] == BRACKETED
            # The independent value is the first point of its 0.01 grid at or above the threshold.
            assert INDEPENDENT[pulse][Om] - 0.01 < bare["beta_min"].values[i] <= INDEPENDENT[pulse][Om], Om


def test_maps_and_spectra_run_every_family_and_record_it(tmp_path):
    outcomes = {}
    for pulse, shape in (("cosine", {}), ("ricker", {}), ("ricker_anti", {}), ("mp", {"gamma_mp": 2.0})):
        setting = Setting(rocking.Block.reference(), pulse=pulse, **shape)
        study = overturning_map(
            setting, Tuning(0.05), Grid("Omega", 2.0, 6.0, 3), Grid("beta", 1.0, 9.0, 3), SERIAL, runs=tmp_path
        )
        assert study.config["pulse"]["motion"] == pulse and study.config["directions"]["signs"] == [1, -1]
        outcomes[pulse] = study.data["overturned"].sel(part="bare").values
        assert outcomes[pulse].any()
    assert not np.array_equal(outcomes["ricker"], outcomes["cosine"])
    assert "pulse" not in Setting(rocking.Block.reference()).record()  # the paper's one-sine keeps its hash


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"pulse": "square"}, r"^pulse must be one of sine, cosine, ricker, ricker_anti, mp"),
     ({"pulse": "mp"}, r"give gamma_mp with pulse='mp'"), ({"gamma_mp": 2.0}, r"give gamma_mp with pulse='mp'")],
)  # fmt: skip
def test_bad_pulse_families_are_refused(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        Setting(rocking.Block.reference(), **kwargs)
