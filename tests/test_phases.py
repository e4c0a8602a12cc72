"""The phase table, declared once (rocking/sim/phases.py), and sim.c's copy of it (csrc/phases.h)."""

import pytest

from rocking.sim import phases


def test_the_c_header_is_written_from_the_table():
    assert phases.HEADER.read_text() == phases.c_header(), "run python -m rocking.sim.phases"


def test_every_exit_names_a_known_event_guard_and_target():
    phases.check_table()


def test_a_floor_without_friction_never_leaves_the_two_stuck_phases():
    """The stuck phases lead to sliding ones on the floor only by the friction's events (or an impact that slides)."""
    for p in phases.PHASES:
        if p.slides:
            continue
        for e in p.exits:
            if e.to in {q.name for q in phases.PHASES if q.slides and not q.flies}:
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
        ("rocking", "lift-off", "always", "flight"),
        ("contact", "lift-off", "always", "flight"),
        ("flight", "landing", "rests", "contact"),
        ("flight", "landing", "rocks-sliding", "slide-rock"),
        ("flight", "landing", "bounces", "flight"),
        ("flight", "landing", "jams", "jammed"),
        ("flight", "overturn", "always", "overturned"),
    ],
)
def test_transitions(current, event, guard, to):
    assert phases.next_phase(current, event, guard) == to
    p = phases.phase(current)
    assert phases.of(p.rocks, p.slides, p.flies).name == current


def test_the_flight_phase_is_entered_only_where_the_floor_lets_go_or_a_landing_bounces():
    """Every phase on the floor leaves it by its lift-off (N = 0); in flight only a bouncing landing stays there."""
    for p in phases.PHASES:
        into = [e for e in p.exits if e.to == "flight"]
        expected = ["bounces"] if p.flies else ["always"]
        assert [e.guard for e in into] == expected and {e.event for e in into} <= set(phases.FLIGHT_EVENTS), p.name
