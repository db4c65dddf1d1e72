"""A hostile user's inputs: each gets a one-line error naming what is wrong and how to fix it, or the right result."""

from __future__ import annotations

import json
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

from sarsp_edu import ExperimentConfig, compare, run_experiment, run_sweep
from sarsp_edu.cli import main

from .test_cli import _usage_error as usage_error


def test_exact_and_numpy_numbers_in_a_config_are_plain_numbers_that_save_as_json():
    config = ExperimentConfig(outlier_magnitude=Decimal("40"), nu=Fraction(7, 2), episodes=np.int64(3))
    assert (config.outlier_magnitude, config.nu, config.episodes) == (40.0, 3.5, 3)
    assert type(config.outlier_magnitude) is float and type(config.episodes) is int
    json.dumps(config.to_dict())  # what save() writes
    with pytest.raises(ValueError, match=r"episodes must be an integer from 1 to 100000 .*got episodes=3.5"):
        ExperimentConfig(episodes=Fraction(7, 2))


@pytest.mark.parametrize("function", [compare, run_experiment, run_sweep])
def test_a_config_of_the_wrong_type_is_named_with_the_type_expected(function):
    with pytest.raises(TypeError, match=r"config must be an ExperimentConfig, got dict; make one with "
                                        r"ExperimentConfig\(\*\*settings\)"):
        function({"episodes": 1})
