"""DRAFT, not collected by pytest (its name is not ``test_*``): the back-end fact the C back end fails.

A test of ``tests/test_flight_backends.py``, run by hand: ``python -m pytest -q -n 0 tests/draft_flight_backends_c.py``.
Once green, "c" joins ``AGREE`` there and this file goes. On main at 531d4e5 it fails: with a damper, C's jump_max is
short by 0.9 to 2.7 % where the highest point is the corner -s's (the raised corner's; the reference corner's peaks
are right): runs 8, 11 and 16 of ``random_cases(20, 40, damper=True)``. Everything else of the 20 + 10 runs agrees
with the reference as NumPy does.
"""

from __future__ import annotations

from tests import test_flight_backends as backends


def test_random_vertical_pulses_are_the_reference():
    """(a) on the C back end: 20 + 10 runs, status, counts and maxima (``tests/test_flight_backends.py``)."""
    backends.test_random_vertical_pulses_are_the_reference("c")
