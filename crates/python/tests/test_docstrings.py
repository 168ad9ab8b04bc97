"""The examples in the docstrings run and print what they show."""

import doctest

import numpy as np
import pytest

import imutherm
import imutherm._curve
import imutherm._recording
import imutherm._tcal
import imutherm.allantools
import imutherm.allantools.noise_kasdin


@pytest.mark.parametrize("module", [imutherm, imutherm._curve, imutherm._recording,
                                    imutherm.allantools, imutherm.allantools.noise_kasdin])
def test_docstring_examples(module):
    result = doctest.testmod(module, extraglobs={"np": np, "imutherm": imutherm},
                             optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0
    assert result.failed == 0
