"""The phases of a run, declared once: what each one integrates, what ends it, and what follows.

docs/simulation.md ("Phases") and docs/model.md section 15. A phase is a set of constraints on the block: its
base in full contact or rocking about a corner ``s``, and the contact stuck or sliding. Each phase names the
generated function of its accelerations and of the floor's force on its contact; each of its exits is an event
(a zero of a function of the state) with the guards that choose the next phase. Both back ends follow this
table: the NumPy one reads it, the C one reads ``csrc/phases.h``, written from it by ``python -m
rocking.sim.phases`` (a test checks that the header is current).

A floor without friction (``mu_s = inf``, the paper's) keeps every run in the two stuck phases, as before
friction was declared: their exits ``slip`` and ``lift-off`` are not watched, and an impact sticks.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Exit:
    """One way a phase ends.

    Attributes
    ----------
    event : str
        The event (:data:`EVENTS`).
    guard : str
        The condition on the state at the event that selects this exit (:data:`GUARDS`); ``"always"``: none.
    to : str
        The next phase, or an end of the run (:data:`ENDS`).
    """

    event: str
    guard: str
    to: str


@dataclass(frozen=True)
class Phase:
    """One phase of the run.

    Attributes
    ----------
    name : str
        How statuses, events and histories call it.
    rocks : bool
        The block rocks about a corner ``s`` (else its base is in full contact, ``theta = dtheta = 0``); in flight,
        ``s`` is the reference corner of the flying state.
    slides : bool
        The contact slides: the slip ``u`` and its speed ``du`` are integrated and the floor's tangential force is
        ``F = -mu_k sign(du) N`` (else ``u`` is held, ``du = 0``, and the floor holds ``|F| <= mu_s N``).
    flies : bool
        The block is off the floor: the reference corner's height ``v`` and its rate ``dv`` are integrated too, and
        the floor holds nothing (docs/model.md section 16).
    accel : str
        The generated function of its accelerations.
    force : str
        The generated function that gives the floor's force on the contact, ``(F, N)`` or ``N`` last; ``""``: none.
    exits : tuple of Exit
        What ends it, in the order the guards are tried for one event.
    """

    name: str
    rocks: bool
    slides: bool
    flies: bool
    accel: str
    force: str
    exits: tuple


#: The events that end a phase, each a zero of a function of the state (docs/simulation.md, "Events").
EVENTS = {
    "uplift": "the uplift function of the phase about s turns positive (sliding: written with the friction force)",
    "impact": "theta returns to 0",
    "overturn": "|theta| reaches pi/2",
    "slip": "the force the stuck contact must hold reaches mu_s N: |F| = mu_s N",
    "stop": "the slip speed du returns to 0",
    "lift-off": "the floor's normal force N on the contact returns to 0",
    "rest": "the energy above rest falls below energy_rest in full contact after the motion (rules 2, 4)",
    "landing": "the height of a base corner above the floor returns to 0 moving down (docs/model.md section 16)",
}

#: The conditions on the state at an event that choose between exits.
GUARDS = {
    "always": "no condition",
    "holds": "the stuck contact's |F| <= mu_s N (after an impact: the impulse |P_t| <= mu_s P_n)",
    "slips": "the stuck contact's |F| > mu_s N (after an impact: |P_t| > mu_s P_n): it slides, du against F",
    "rests": "after an impact the corner holds and |dtheta| < dtheta_rest: the block rests on its base (rule 2)",
    "rocks": "after an impact the corner holds and |dtheta| >= dtheta_rest: it rocks on about that corner, -s",
    "rests-sliding": "after an impact the corner slides through it and |dtheta| < dtheta_rest",
    "rocks-sliding": "after an impact the corner slides through it and |dtheta| >= dtheta_rest",
    "bounces": "after a landing the corner leaves the floor again: dv after it (-e_n dv before) above the bounce speed",
    "jams": "a landing with no consistent impulse (Painleve's jam: neither sticking nor sliding holds)",
}

#: How a run can end in a phase (statuses of :data:`rocking.sim.boundary.STATUSES`).
ENDS = ("overturned", "rest", "jammed")

#: The phases, in the order of their codes (a phase's code is its index in this table, as csrc/phases.h numbers them).
PHASES = (
    Phase(
        "contact",
        rocks=False,
        slides=False,
        flies=False,
        accel="contact_accel",
        force="contact_stick_force",
        exits=(
            Exit("uplift", "always", "rocking"),
            Exit("slip", "always", "contact-slide"),
            Exit("lift-off", "always", "flight"),
            Exit("rest", "always", "rest"),
        ),
    ),
    Phase(
        "contact-slide",
        rocks=False,
        slides=True,
        flies=False,
        accel="contact_slide_accel",
        force="contact_slide_accel",
        exits=(
            Exit("uplift", "always", "slide-rock"),
            Exit("stop", "holds", "contact"),
            Exit("stop", "slips", "contact-slide"),
            Exit("lift-off", "always", "flight"),
        ),
    ),
    Phase(
        "rocking",
        rocks=True,
        slides=False,
        flies=False,
        accel="rocking_accel",
        force="stick_force",
        exits=(
            Exit("impact", "rests", "contact"),
            Exit("impact", "rocks", "rocking"),
            Exit("impact", "rests-sliding", "contact-slide"),
            Exit("impact", "rocks-sliding", "slide-rock"),
            Exit("slip", "always", "slide-rock"),
            Exit("lift-off", "always", "flight"),
            Exit("overturn", "always", "overturned"),
        ),
    ),
    Phase(
        "slide-rock",
        rocks=True,
        slides=True,
        flies=False,
        accel="slide_accel",
        force="slide_accel",
        exits=(
            Exit("impact", "rests", "contact"),
            Exit("impact", "rocks", "rocking"),
            Exit("impact", "rests-sliding", "contact-slide"),
            Exit("impact", "rocks-sliding", "slide-rock"),
            Exit("stop", "holds", "rocking"),
            Exit("stop", "slips", "slide-rock"),
            Exit("lift-off", "always", "flight"),
            Exit("overturn", "always", "overturned"),
        ),
    ),
    Phase(
        "flight",
        rocks=True,
        slides=True,
        flies=True,
        accel="flight_accel",
        force="",
        exits=(
            Exit("landing", "rests", "contact"),
            Exit("landing", "rocks", "rocking"),
            Exit("landing", "rests-sliding", "contact-slide"),
            Exit("landing", "rocks-sliding", "slide-rock"),
            Exit("landing", "bounces", "flight"),
            Exit("landing", "jams", "jammed"),
            Exit("overturn", "always", "overturned"),
        ),
    ),
)

#: The events each phase watches only on a floor with friction (``mu_s`` finite).
FRICTION_EVENTS = ("slip", "stop")
#: The events each phase watches only on a model with flight functions (``[ground] flight = true``); a model
#: without them ends the run with the status ``flight`` where the table enters the flight phase (section 14).
FLIGHT_EVENTS = ("lift-off", "landing")


def phase(name: str) -> Phase:
    """The phase called ``name``."""
    for p in PHASES:
        if p.name == name:
            return p
    raise KeyError(name)


def of(rocks: bool, slides: bool, flies: bool = False) -> Phase:
    """The phase with these constraints."""
    for p in PHASES:
        if (p.rocks, p.slides, p.flies) == (rocks, slides, flies):
            return p
    raise KeyError((rocks, slides, flies))


def next_phase(current: str, event: str, guard: str) -> str:
    """Where ``event`` under ``guard`` leads from the phase ``current`` (a phase's name or an end)."""
    for e in phase(current).exits:
        if e.event == event and e.guard in (guard, "always"):
            return e.to
    raise KeyError((current, event, guard))


def check_table() -> None:
    """Every exit names a known event, guard and target; every phase's flags are its own.

    Raises
    ------
    ValueError
        Naming the first entry that is not.
    """
    names = {p.name for p in PHASES}
    if len({(p.rocks, p.slides, p.flies) for p in PHASES}) != len(PHASES):
        raise ValueError("two phases have the same constraints")
    for p in PHASES:
        for e in p.exits:
            if not (e.event in EVENTS and e.guard in GUARDS and (e.to in names or e.to in ENDS)):
                raise ValueError(f"phase {p.name}: exit {e} names an unknown event, guard or target")


HEADER = Path(__file__).parent / "csrc" / "phases.h"


def _c_name(name: str) -> str:
    return name.upper().replace("-", "_")


def c_header() -> str:
    """``csrc/phases.h``: the table for sim.c, the same data as :data:`PHASES`."""
    lines = [
        "/* The phases of a run: generated by `python -m rocking.sim.phases` from rocking/sim/phases.py, do not edit.",
        ' * docs/simulation.md, "Phases"; a phase\'s code is its index in PHASES. */',
        "#ifndef ROCKING_PHASES_H",
        "#define ROCKING_PHASES_H",
        "",
    ]
    lines += [f"#define PHASE_{_c_name(p.name)} {i}" for i, p in enumerate(PHASES)]
    lines += [f"#define PHASE_COUNT {len(PHASES)}", ""]
    lines += [f"#define PHASE_EVENT_{_c_name(e)} {i}" for i, e in enumerate(EVENTS)]
    lines += [f"#define PHASE_GUARD_{_c_name(g)} {i}" for i, g in enumerate(GUARDS)]
    ends = {end: -1 - i for i, end in enumerate(ENDS)}
    lines += [f"#define PHASE_END_{_c_name(end)} ({v})" for end, v in ends.items()]
    width = max(len(p.exits) for p in PHASES)

    def target(to: str) -> str:
        return f"PHASE_END_{_c_name(to)}" if to in ends else f"PHASE_{_c_name(to)}"

    lines += [
        "",
        f"#define PHASE_MAX_EXITS {width}",
        "",
        "/* One exit: the event, the guard that selects it, the next phase (>= 0) or an end (< 0). */",
        "typedef struct phase_exit {",
        "    int event, guard, to;",
        "} phase_exit;",
        "",
        "/* One phase: rocks about s (else full contact), slides (u, du integrated), flies (v, dv too), its exits. */",
        "typedef struct phase_rule {",
        "    const char *name;",
        "    int rocks, slides, flies, n_exits;",
        "    phase_exit exits[PHASE_MAX_EXITS];",
        "} phase_rule;",
        "",
        "static const phase_rule PHASES[PHASE_COUNT] = {",
    ]
    for p in PHASES:
        exits = ", ".join(
            f"{{PHASE_EVENT_{_c_name(e.event)}, PHASE_GUARD_{_c_name(e.guard)}, {target(e.to)}}}" for e in p.exits
        )
        flags = f"{int(p.rocks)}, {int(p.slides)}, {int(p.flies)}"
        lines.append(f'    {{"{p.name}", {flags}, {len(p.exits)}, {{{exits}}}}},')
    lines += ["};", "", "#endif", ""]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Write ``csrc/phases.h``; ``--check``: exit 1 if it is not current."""
    args = sys.argv[1:] if argv is None else argv
    text = c_header()
    if "--check" in args:
        current = HEADER.exists() and HEADER.read_text() == text
        print(f"{HEADER}: {'current' if current else 'stale: run python -m rocking.sim.phases'}")
        return 0 if current else 1
    HEADER.write_text(text)
    print(f"wrote {HEADER}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
