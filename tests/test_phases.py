"""The phase table, declared once (rocking/sim/phases.py), and sim.c's copy of it (csrc/phases.h)."""

import pytest

from rocking.sim import phases


def test_the_c_header_is_written_from_the_table():
    assert phases.HEADER.read_text() == phases.c_header(), "run python -m rocking.sim.phases"


def test_every_exit_names_a_known_event_guard_and_target():
    phases.check_table()


def test_a_floor_without_friction_never_leaves_the_two_stuck_phases():
    """The stuck phases lead to sliding ones only by the friction's events (or an impact that slides)."""
    for p in phases.PHASES:
        if p.slides:
            continue
        for e in p.exits:
            if e.to in {q.name for q in phases.PHASES if q.slides}:
                assert e.event in phases.FRICTION_EVENTS or e.guard.endswith("-sliding"), (p.name, e)


@pytest.mark.parametrize(
    "current, event, guard, to",
    [
        ("contact", "uplift", "always", "rocking"),
        ("contact", "slip", "always", "contact-slide"),
        ("contact-slide", "stop", "holds", "contact"),
        ("contact-slide", "stop", "slips", "contact-slide"),
        ("contact-slide", "uplift", "always", "slide-rock"),
        ("rocking", "impact", "rests", "contact"),
        ("rocking", "impact", "rocks-sliding", "slide-rock"),
        ("slide-rock", "stop", "holds", "rocking"),
        ("slide-rock", "overturn", "always", "overturned"),
    ],
)
def test_transitions(current, event, guard, to):
    assert phases.next_phase(current, event, guard) == to
    assert phases.of(phases.phase(current).rocks, phases.phase(current).slides).name == current
