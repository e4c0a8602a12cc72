"""The boundary between the simulator's two back ends and their callers, declared once.

One table each for what a run is given (:data:`CASE`), what it answers
(:data:`RESULT`), why it ended (:data:`STATUSES`), the phase codes
(:data:`PHASES`) and the constants both back ends use (:data:`CONSTANTS`).
Everything else is built from them: the C declarations of ``csrc/boundary.h``
(:func:`c_header`), the ctypes structures and NumPy records of
:mod:`rocking.sim.c_backend`, the typed fields of :class:`~rocking.sim.problem.Problem`
and :class:`~rocking.sim.problem.Response` (``fields.py``, :func:`python_fields`), the checks
of every setting (:func:`check`) and the table of ``docs/simulation.md`` (:func:`markdown`).
The C library reports its layout and constants when it is loaded, and the
loader refuses a library that disagrees with these tables.

Adding a setting is one :class:`Field` in :data:`CASE` plus its use in the
two back ends. ``python -m rocking.sim.boundary`` rewrites ``csrc/boundary.h``,
``fields.py`` and the table of ``docs/simulation.md``; a test fails while any is stale.

Units SI.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..model import motion
from ..model.checks import RANGES, ParameterError, shown

#: Bumped whenever :data:`CASE`, :data:`RESULT` or an entry point of ``sim.h`` changes.
API_VERSION = 10

DOUBLE, INT64, INT32, DOUBLES, SERIES = "double", "int64", "int32", "doubles", "series"

#: C type of each kind of field (``DOUBLES``: a caller-owned array of state values; ``SERIES``: a caller-owned
#: array of as many values as the field's ``count`` says, which the cases of a batch may share).
C_TYPES = {DOUBLE: "double", INT64: "int64_t", INT32: "int32_t", DOUBLES: "const double *", SERIES: "const double *"}

_REQUIRED = object()

#: The range of an ``int64_t`` field.
INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1

#: Default of ``max_steps`` (docs/simulation.md, rule 5): far above what any response
#: of the bench map needs, and a few seconds of the NumPy back end at most.
MAX_STEPS_DEFAULT = 300_000


@dataclass(frozen=True)
class Field:
    """One field of a C structure and of its Python counterparts.

    Attributes
    ----------
    name : str
        The same in C, in Python and in the documentation.
    kind : str
        :data:`DOUBLE`, :data:`INT64`, :data:`INT32`, :data:`DOUBLES` (one
        value per state component, ``model_ny()`` of them) or :data:`SERIES`
        (``count`` values).
    unit : str
        SI unit, ``""`` for a pure number.
    doc : str
        What it is, in one line.
    valid : str or None
        The check of the setting: an entry of :data:`~rocking.model.checks.RANGES` (its bounds are
        declared there only), a key of :data:`CODES`, or ``None``: not checked (an array, or a result).
    default : object
        Value of a :class:`~rocking.sim.problem.Problem` that does not give it.
    count : str or None
        For a :data:`SERIES`: the :data:`INT64` field holding its length.
    """

    name: str
    kind: str
    unit: str
    doc: str
    valid: str | None = None
    default: object = _REQUIRED
    count: str | None = None

    def __post_init__(self) -> None:
        if (self.kind == SERIES) != (self.count is not None):  # what a Problem's checks of the series rely on
            raise ValueError(f"field {self.name!r}: a SERIES has a count, no other field has one")

    @property
    def required(self) -> bool:
        return self.default is _REQUIRED


#: What one run is given besides the model's parameters: ``rocking_case`` of sim.h.
CASE = (
    Field(
        "motion",
        INT32,
        "",
        "ground-motion family: an index into MOTIONS (docs/model.md section 12)",
        "a code of MOTIONS",
        0,
    ),
    Field("a_g", DOUBLE, "m/s^2", "signed amplitude: ag(t) = a_g f(t) on [0, t_p], 0 after", "real"),
    Field("omega_g", DOUBLE, "rad/s", "circular frequency of f (0 for a sampled motion)", "real"),
    Field("psi", DOUBLE, "rad", "phase of f: psi of the one-sine, nu of Mavroeidis-Papageorgiou", "real"),
    Field("t_c", DOUBLE, "s", "centre of a Ricker or Mavroeidis-Papageorgiou pulse", "real", 0.0),
    Field("shape", DOUBLE, "", "gamma of Mavroeidis-Papageorgiou (0 otherwise)", "real", 0.0),
    Field("t_p", DOUBLE, "s", "end of the motion, a breakpoint of the integration", "real"),
    Field("n_extrema", INT64, "", "number of listed extrema", "count", 0),
    Field(
        "extrema",
        SERIES,
        "rad",
        "extrema of f (and of the uplift margins with a vertical lead) in omega_g (t - t_c), sorted, "
        "for the sine and cosine pulses the margins' extrema in the sine's argument, mod pi",
        None,
        None,
        "n_extrema",
    ),
    Field("pulse_dt", DOUBLE, "s", "spacing of a sampled motion's samples (0 otherwise)", "nonnegative", 0.0),
    Field("n_samples", INT64, "", "number of samples of a sampled motion (0 otherwise)", "count", 0),
    Field("samples", SERIES, "m/s^2", "samples a_k at k pulse_dt: f linear between them", None, None, "n_samples"),
    Field(
        "a_v",
        DOUBLE,
        "m/s^2",
        "vertical amplitude, > 0 up: agy(t) = a_v f_v(t) on [0, t_p], 0 after (docs/model.md section 14); 0: none",
        "real",
        0.0,
    ),
    Field("psi_v", DOUBLE, "rad", "lead of the vertical shape: f_v(t) = f(t + psi_v / omega_g)", "real", 0.0),
    Field("n_v_samples", INT64, "", "number of vertical samples of a sampled motion (0: none)", "count", 0),
    Field(
        "v_samples",
        SERIES,
        "m/s^2",
        "a sampled motion's vertical samples at k pulse_dt: f_v linear between them",
        None,
        None,
        "n_v_samples",
    ),
    Field(
        "t_flight",
        DOUBLE,
        "s",
        "first time g + agy(t) <= 0, from the motion: a model without flight functions ends there with status "
        "flight (inf: never, and for a model with them, which flies)",
        None,
        math.inf,
    ),
    Field(
        "mu_s",
        DOUBLE,
        "",
        "static Coulomb friction of the floor (docs/model.md section 15); inf: the base never slides",
        "mu",
        math.inf,
    ),
    Field("mu_k", DOUBLE, "", "kinetic Coulomb friction of the floor, <= mu_s (inf with mu_s = inf)", "mu", math.inf),
    Field(
        "e_n",
        DOUBLE,
        "",
        "normal restitution of a landing (docs/model.md section 16): 0 plastic (the default), 1 elastic",
        "e_n",
        0.0,
    ),
    Field("t_max", DOUBLE, "s", "end of the run if nothing ends it first", "t_max"),
    Field("rtol", DOUBLE, "", "relative tolerance of the integrator", "rtol"),
    Field("atol", DOUBLES, "state units", "absolute tolerance of each state component"),
    Field("contact_max_step", DOUBLE, "s", "largest step in full contact while t < t_p", "positive"),
    Field("dtheta_rest", DOUBLE, "rad/s", "an impact with outgoing |dtheta| below this ends rocking", "nonnegative"),
    Field(
        "energy_rest", DOUBLE, "J", "full contact after the pulse ends once E(y) - E(0) is below this", "nonnegative"
    ),
    Field("max_events", INT64, "", "the run ends when uplifts + impacts + flights reach this", "max_events"),
    Field(
        "max_steps",
        INT64,
        "",
        "bound on the work of a run: right-hand-side evaluations plus recorded samples (rule 5)",
        "max_steps",
        MAX_STEPS_DEFAULT,
    ),
    Field("record_dt", DOUBLE, "s", "spacing of a recorded history (<= 0: events only)", "real", 0.0),
    Field("y0", DOUBLES, "state units", "initial state (NULL / None: at rest)", None, None),
    Field("phase0", INT32, "", "initial phase: 0 full contact, +1 / -1 rocking about A / A'", "-1, 0 or +1", 0),
    Field("early_rest", INT32, "", "1: below the uplift energy after the pulse, end at the next extremum", "0 or 1", 1),
    Field(
        "early_verdict",
        INT32,
        "",
        "1: after the pulse, end once the energy keeps |theta| and |q[1]| below their maxima (rule 4)",
        "0 or 1",
        1,
    ),
)

#: What one run answers: ``rocking_result`` of sim.h (ordered so that the C structure has no padding).
RESULT = (
    Field("status", INT32, "", "why the run ended: an index into STATUSES"),
    Field("overturned", INT32, "", "|theta| reached pi/2"),
    Field("impacts", INT64, "", "impacts at theta = 0"),
    Field("uplifts", INT64, "", "uplifts from full contact"),
    Field("t_overturn", DOUBLE, "s", "when |theta| reached pi/2 (NaN if it did not)"),
    Field("t_critical", DOUBLE, "s", "first time |theta| passed the static critical angle (NaN: never)"),
    Field("theta_max", DOUBLE, "rad", "largest |theta|"),
    Field("x_max", DOUBLE, "m", "largest |q[1]|, the damper's stroke (0 without a damper)"),
    Field("t_end", DOUBLE, "s", "when the run ended"),
    Field(
        "stop_contacts",
        INT64,
        "",
        "times an end stop's pad starts pushing: its gap closes, a released pad pushes again, or an impact makes it"
        " push (0 without stops); final at rest and bounded (rules 4, 6)",
    ),
    Field(
        "bumper_force_max",
        DOUBLE,
        "N",
        "largest force of a bumper against its penetration, the peak of the dense output (rule 6)",
    ),
    # A back end that does not follow friction leaves these at their defaults, the answer of a floor with mu = inf.
    Field("u_max", DOUBLE, "m", "largest |u|, the peak slip of the base relative to the ground", None, 0.0),
    Field("u_end", DOUBLE, "m", "the residual displacement of the base: u at the end (signed)", None, 0.0),
    Field("slides", INT64, "", "slip episodes: times the base started sliding on the floor", None, 0),
    # A back end or a model that does not follow flight leaves these at 0: such a run ends with the status flight.
    Field(
        "flight_time", DOUBLE, "s", "the total time the block spent off the floor (docs/model.md section 16)", None, 0.0
    ),
    Field(
        "jump_max",
        DOUBLE,
        "m",
        "largest height above the floor a base corner reached in flight (the highest base point's peak)",
        None,
        0.0,
    ),
    Field("flights", INT64, "", "takeoffs: times the block left the floor", None, 0),
)


#: The results the tolerance check (:mod:`rocking.sim.accuracy`) adds to a :class:`~rocking.sim.problem.Response`:
#: Python's alone, never in the C boundary; their defaults are those of a response that no check ran on.
CHECKED = (
    Field(
        "sensitive",
        INT32,
        "",
        "the tolerance check's runs disagree (the verdict, or theta_max or x_max by more than 10 %): this response is "
        "its tightest run's (docs/simulation.md, Sensitivity to the tolerance)",
        None,
        0,
    ),
    Field(
        "theta_max_low",
        DOUBLE,
        "rad",
        "smallest theta_max of the tolerance check's runs (NaN: not checked)",
        None,
        math.nan,
    ),
    Field(
        "theta_max_high",
        DOUBLE,
        "rad",
        "largest theta_max of the tolerance check's runs (NaN: not checked)",
        None,
        math.nan,
    ),
    Field(
        "overturned_fraction",
        DOUBLE,
        "",
        "fraction of the tolerance check's runs that overturned (NaN: not checked)",
        None,
        math.nan,
    ),
    Field("check_runs", INT64, "", "runs behind this response: 1 without the tolerance check", None, 1),
)
#: The result that marks a response whose tolerance check's runs disagree.
SENSITIVE = CHECKED[0]

#: The fields of a :class:`~rocking.sim.problem.Response`: the C results, then the tolerance check's.
SUMMARY = (*RESULT, *CHECKED)

#: Python type of each kind of field.
PYTHON_TYPES = {DOUBLE: float, INT64: int, INT32: int, DOUBLES: np.ndarray, SERIES: np.ndarray}
#: Fields whose Python value is not their C number: a name of :data:`STATUS`, truth values.
NAMED_PYTHON_TYPES = {"status": str, "overturned": bool, "early_rest": bool, "early_verdict": bool, "sensitive": bool}


def python_type(f: Field) -> type:
    """The Python type of a field of :data:`CASE` or :data:`SUMMARY`."""
    return NAMED_PYTHON_TYPES.get(f.name, PYTHON_TYPES[f.kind])


@dataclass(frozen=True)
class Code:
    """A named integer code shared by C and Python."""

    name: str
    value: int
    doc: str


#: Why a run ended; ``STATUSES[i].value == i``, and :data:`FAILED` is C's alone.
STATUSES = (
    Code("overturned", 0, "|theta| reached pi/2"),
    Code("rest", 1, "back in full contact after the pulse, below energy_rest or below the uplift energy"),
    Code("t_max", 2, "t_max reached"),
    Code("max_events", 3, "uplifts + impacts + flights reached max_events"),
    Code("max_steps", 4, "the work of the run passed max_steps (rule 5)"),
    Code("bounded", 5, "after the pulse, the energy keeps |theta| and |q[1]| below their maxima: final (rule 4)"),
    Code(
        "flight",
        6,
        "the floor's normal force reached 0 on a model without flight functions: the base may leave the ground, out "
        "of its scope (docs/model.md sections 14, 16)",
    ),
    Code(
        "below_barrier",
        7,
        "t_max reached after the pulse, the energy below the least potential on the way to overturning: safe, its "
        "maxima those until t_max (rule 4)",
    ),
    Code(
        "jammed",
        8,
        "a landing with no consistent impulse, neither sticking nor sliding (Painleve's jam, docs/model.md section "
        "16): out of the model, no verdict",
    ),
)
#: Status code of a run whose step size underflowed (a non-finite right-hand side); never a result.
FAILED = Code("failed", -1, "the step size underflowed (non-finite right-hand side, ...)")
#: Status code of a run stopped by its caller's stop flag (``rocking_control.stop``); never a result.
STOPPED = Code("stopped", -2, "stopped by the caller's stop flag (Python: KeyboardInterrupt)")

#: Ground-motion families (docs/model.md section 12), the ``motion`` of a case.
MOTIONS = tuple(
    Code(name, i, doc)
    for i, (name, doc) in enumerate(
        zip(
            motion.FAMILIES,
            (
                "one-sine: f = sin(omega_g t + psi)",
                "one-cosine: f = cos(omega_g t)",
                "Ricker wavelet: f = (1 - 2 u^2) exp(-u^2), u = omega_g (t - t_c) / 2",
                "antisymmetric Ricker wavelet: f = -u (3 - 2 u^2) exp(-u^2) / RICKER_ANTI_PEAK, "
                "u = omega_g (t - t_c) / sqrt 6",
                "Mavroeidis-Papageorgiou: the derivative of its velocity pulse (docs/model.md section 12)",
                "sampled: the samples, linear between them",
            ),
            strict=True,
        )
    )
)

#: Phase codes of a recorded history and of ``phase0``.
PHASES = (
    Code("contact", 0, "full contact: theta = dtheta = 0"),
    Code("pivot_a", 1, "rocking about the corner A (s = +1, theta > 0)"),
    Code("pivot_a_prime", -1, "rocking about the corner A' (s = -1, theta < 0)"),
)


@dataclass(frozen=True)
class Constant:
    """A number both back ends use."""

    name: str
    value: float
    doc: str


CONSTANTS = (
    Constant("SAFE_MARGIN", 1e-9, "relative margin below the energy bounds of the early rest and verdict (rule 4)"),
    Constant("ARC_STEP", 0.05, "widest arc of tilts [rad] on which the early verdict bounds the potential (rule 4)"),
    Constant("FIRST_STEP_FRACTION", 0.25, "first step after an impact, as a fraction of the expected half-cycle"),
    Constant("RICKER_ANTI_PEAK", motion.RICKER_ANTI_PEAK, "peak of u (3 - 2 u^2) exp(-u^2), at u^2 = (3 - sqrt 6) / 2"),
    Constant("BARRIER_TILTS", 64, "a run at t_max is bounded at the tilts k pi / (2 BARRIER_TILTS), 0 < k < it"),
    Constant(
        "FLAT_LANDING",
        1e-13,
        "a landing is flat, on both corners, where |sin theta| is at most this (docs/model.md section 16): rounding",
    ),
    Constant(
        "TAKEOFF_PROBE",
        1e-6,
        "a stuck corner of a floor without friction whose free flight does not lift it at N = 0 is tried this much "
        "later [s] along the flight (docs/simulation.md, Flight)",
    ),
)

STATUS = tuple(code.name for code in STATUSES)
#: Statuses of a run cut short by a bound on its work: whether the block would overturn is not known.
UNDETERMINED = ("max_events", "max_steps")
CONTACT, PIVOT_A, PIVOT_A_PRIME = (code.value for code in PHASES)
SAFE_MARGIN, ARC_STEP, FIRST_STEP_FRACTION, _, _TILTS, FLAT_LANDING, TAKEOFF_PROBE = (c.value for c in CONSTANTS)
BARRIER_TILTS = int(_TILTS)
#: The code of each ground-motion family by name.
MOTION = {code.name: code.value for code in MOTIONS}

assert all(code.value == i for i, code in enumerate(STATUSES))

#: The settings that are codes, not numbers in a range: the valid values by the phrase of the message.
CODES = {
    "a code of MOTIONS": tuple(code.value for code in MOTIONS),
    "-1, 0 or +1": tuple(code.value for code in PHASES),
    "0 or 1": (0, 1),
}


#: The check of each setting by name (None: unchecked), looked up once per process.
_VALID = {f.name: f.valid for f in CASE}


def field_named(table: tuple[Field, ...], name: str) -> Field:
    """The field ``name`` of ``table``."""
    return next(f for f in table if f.name == name)


# --------------------------------------------------------------------------- #
# Checks                                                                       #
# --------------------------------------------------------------------------- #


def check(name: str, value):
    """``value`` of the case field ``name`` if it passes the field's check (elementwise), else raise.

    Raises
    ------
    ParameterError
        Naming the setting, its valid range and the first offending value.
    """
    valid = _VALID[name] if name in _VALID else field_named(CASE, name).valid
    if valid is None:
        return value
    if isinstance(value, (float, int, np.integer)):  # one number (a single run; a bool is 0 or 1): as it is
        # An int beyond int64 fits no field of the C structure (nor, beyond the doubles, a double).
        if not (holds(valid, value) and (isinstance(value, float) or INT64_MIN <= value <= INT64_MAX)):
            raise ParameterError(f"{name} must be {valid_text(valid)} (got {_shown(value)})")
        return value
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be {valid_text(valid)} (got {shown(value)})") from None
    ok = holds(valid, a)
    if not np.all(ok):
        bad = a[~ok].ravel()[0] if a.ndim else a
        raise ParameterError(f"{name} must be {valid_text(valid)} (got {_shown(bad)})")
    return value


def holds(valid: str, value):
    """Elementwise: ``value`` (a number or an array) passes the check ``valid`` of a field."""
    codes = CODES.get(valid)
    if codes is None:
        return RANGES[valid].holds(value)
    return np.isin(value, codes) if isinstance(value, np.ndarray) else value in codes


def valid_text(valid: str) -> str:
    """The valid values of the check ``valid`` as a phrase: ``"finite and > 0"``, ``"an integer >= 1"``, ..."""
    return valid if valid in CODES else RANGES[valid].rule()


def _shown(value: float | np.integer | np.ndarray) -> str:
    if isinstance(value, (int, np.integer)):
        return shown(value)  # exactly, or by its magnitude beyond the doubles
    value = float(value)
    return repr(int(value)) if math.isfinite(value) and value == int(value) else repr(value)


# --------------------------------------------------------------------------- #
# Generated text: the C header and the documentation                           #
# --------------------------------------------------------------------------- #

HEADER = Path(__file__).resolve().parent / "csrc" / "boundary.h"
FIELDS = Path(__file__).resolve().parent / "fields.py"
DOC = Path(__file__).resolve().parents[2] / "docs" / "simulation.md"
DOC_BEGIN, DOC_END = "<!-- boundary table: begin -->", "<!-- boundary table: end -->"


def _c_struct(name: str, fields: tuple[Field, ...]) -> list[str]:
    lines = [f"typedef struct {name} {{"]
    for f in fields:
        unit = f" [{f.unit}]" if f.unit else ""
        ctype = C_TYPES[f.kind]
        lines.append(f"    {ctype}{'' if ctype.endswith('*') else ' '}{f.name}; /* {f.doc}{unit} */")
    return [*lines, f"}} {name};", ""]


def _c_enum(name: str, prefix: str, codes) -> list[str]:
    lines = [f"enum {name} {{"]
    lines += [f"    {prefix}{c.name.upper()} = {c.value}, /* {c.doc} */" for c in codes]
    return [*lines, "};", ""]


def _x_macro(name: str, fields: tuple[Field, ...]) -> list[str]:
    return [f"#define {name}(X) " + " ".join(f"X({f.name})" for f in fields), ""]


def c_header() -> str:
    """The text of ``csrc/boundary.h``: the C side of these tables."""
    lines = [
        "/* Generated by `python -m rocking.sim.boundary` from rocking/sim/boundary.py: do not edit. */",
        "#ifndef ROCKING_BOUNDARY_H",
        "#define ROCKING_BOUNDARY_H",
        "",
        "#include <stdint.h>",
        "",
        f"#define ROCKING_SIM_API_VERSION {API_VERSION}",
        "",
    ]
    lines += [f"#define ROCKING_{c.name} {c.value!r} /* {c.doc} */" for c in CONSTANTS] + [""]
    lines += _c_enum("rocking_status", "ROCKING_", (*STATUSES, FAILED, STOPPED))
    lines += _c_enum("rocking_phase", "ROCKING_", PHASES)
    lines += _c_enum("rocking_motion", "ROCKING_MOTION_", MOTIONS)
    lines += _c_struct("rocking_case", CASE) + _c_struct("rocking_result", RESULT)
    lines += ["/* The fields in table order, for the layout the library reports (rocking_layout). */"]
    lines += _x_macro("ROCKING_CASE_FIELDS", CASE) + _x_macro("ROCKING_RESULT_FIELDS", RESULT)
    lines += ["/* The constants in table order (rocking_constants). */"]
    codes = [f"ROCKING_{c.name.upper()}" for c in (*STATUSES, FAILED, STOPPED, *PHASES)]
    codes += [f"ROCKING_MOTION_{c.name.upper()}" for c in MOTIONS]
    values = [f"ROCKING_{c.name}" for c in CONSTANTS] + codes
    lines += ["#define ROCKING_CONSTANTS(X) " + " ".join(f"X({v})" for v in values), ""]
    return "\n".join([*lines, "#endif", ""])


def _annotation(f: Field) -> str:
    kind = python_type(f)
    name = "np.ndarray" if kind is np.ndarray else kind.__name__
    return f"{name} | None" if f.default is None else name


def _python_field(f: Field) -> str:
    if f.required:
        return f"    {f.name}: {_annotation(f)}"
    default = None if f.default is None else python_type(f)(f.default)
    shown_default = "math.inf" if default == math.inf else "math.nan" if default != default else repr(default)
    return f"    {f.name}: {_annotation(f)} = {shown_default}"


def _python_attributes(fields: tuple[Field, ...]) -> list[str]:
    lines = []
    for f in fields:
        unit = f" [{f.unit}]" if f.unit else ""
        text = f"{f.doc[0].upper()}{f.doc[1:]}{unit}."
        lines += [f"    {f.name} : {_annotation(f)}"]
        lines += textwrap.wrap(text, 112, initial_indent="        ", subsequent_indent="        ")
    return lines


def python_fields() -> str:
    """The text of ``fields.py``: the typed fields of :class:`~rocking.sim.problem.Problem` and ``Response``."""
    return "\n".join(
        [
            '"""Generated by `python -m rocking.sim.boundary` from rocking/sim/boundary.py: do not edit.',
            "",
            "The fields of :class:`~rocking.sim.problem.Problem` (the model, its parameters, then",
            ":data:`~rocking.sim.boundary.CASE`) and of :class:`~rocking.sim.problem.Response`",
            "(:data:`~rocking.sim.boundary.SUMMARY`), as classes that type checkers and editors read;",
            "the classes of :mod:`rocking.sim.problem` add their checks and methods.",
            '"""',
            "",
            "from __future__ import annotations",
            "",
            "import math",
            "from dataclasses import dataclass",
            "",
            "import numpy as np",
            "",
            "from ..model.loading import Model",
            "",
            "",
            "@dataclass(frozen=True, kw_only=True)",
            "class ProblemFields:",
            '    """What one run is given: ``rocking_case`` of sim.h, with the model and its parameters.',
            "",
            "    Attributes",
            "    ----------",
            "    model : Model",
            "        The generated model.",
            "    p : np.ndarray",
            "        Parameters in the model's order.",
            *_python_attributes(CASE),
            '    """',
            "",
            "    model: Model",
            "    p: np.ndarray",
            *(_python_field(f) for f in CASE),
            "",
            "",
            "@dataclass",
            "class ResponseFields:",
            '    """What one run answers: ``rocking_result`` of sim.h, then the tolerance check\'s result.',
            "",
            "    Attributes",
            "    ----------",
            *_python_attributes(SUMMARY),
            '    """',
            "",
            *(_python_field(f) for f in SUMMARY),
            "",
        ]
    )


def constant_values() -> tuple[float, ...]:
    """What ``rocking_constants`` of the C library must report, in its order."""
    named: tuple[Constant | Code, ...] = (*CONSTANTS, *STATUSES, FAILED, STOPPED, *PHASES, *MOTIONS)
    return tuple(float(c.value) for c in named)


def _md_rows(fields: tuple[Field, ...], with_valid: bool) -> list[str]:
    rows = []
    for f in fields:
        cells = [f"`{f.name}`", f.kind, f.unit or "-"]
        if with_valid:
            cells.append(valid_text(f.valid) if f.valid else "-")
            cells.append("-" if f.required else f"`{f.default!r}`")
        rows.append("| " + " | ".join([*cells, f.doc.replace("|", "\\|")]) + " |")
    return rows


def markdown() -> str:
    """The table of ``docs/simulation.md``: settings, results, statuses, phases, constants."""
    lines = [
        DOC_BEGIN,
        "",
        "Generated from `rocking/sim/boundary.py` by `python -m rocking.sim.boundary`.",
        "",
        "Settings of a run (`Problem`, `rocking_case`):",
        "",
        "| field | type | unit | valid | default | meaning |",
        "| --- | --- | --- | --- | --- | --- |",
        *_md_rows(CASE, True),
        "",
        "Results of a run (`Response`, `rocking_result`):",
        "",
        "| field | type | unit | meaning |",
        "| --- | --- | --- | --- |",
        *_md_rows(RESULT, False),
        "",
        "Statuses: " + "; ".join(f"`{c.name}` ({c.value}): {c.doc}" for c in (*STATUSES, FAILED, STOPPED)) + ".",
        "",
        "Phases: " + "; ".join(f"`{c.name}` ({c.value}): {c.doc}" for c in PHASES) + ".",
        "",
        "Motions: " + "; ".join(f"`{c.name}` ({c.value}): {c.doc}" for c in MOTIONS) + ".",
        "",
        "Constants: " + "; ".join(f"`{c.name}` = {c.value!r}: {c.doc}" for c in CONSTANTS) + ".",
        "",
        "Ranges of the public API and of the settings above (`rocking.model.checks.RANGES`, the one table",
        "of bounds, each setting's check an entry of it; `Block`, `Damper`, the motions,",
        "their `from_nondim`, `make_problem`, `simulate` and the studies refuse anything outside, with",
        "the reason, in one line naming the parameter and its range; so is a value that is no real number",
        "(a string, None, a bool, a complex number, an array), nan or infinite, or an integer beyond the",
        "doubles, `10**400`, shown by its magnitude):",
        "",
        "| parameter | valid | why |",
        "| --- | --- | --- |",
        *(f"| `{name}` | {valid.text()} | {valid.why} |" for name, valid in RANGES.items()),
        "",
        DOC_END,
    ]
    return "\n".join(lines)


def document(text: str) -> str:
    """``text`` (of ``docs/simulation.md``) with its boundary table replaced by :func:`markdown`."""
    head, begin, rest = text.partition(DOC_BEGIN)
    _, end, tail = rest.partition(DOC_END)
    if not (begin and end):
        raise ValueError(f"{DOC} has no {DOC_BEGIN} ... {DOC_END} block")
    return head + markdown() + tail


def main() -> int:
    """Rewrite ``csrc/boundary.h``, ``fields.py`` and the table of ``docs/simulation.md`` from the tables."""
    HEADER.write_text(c_header(), encoding="utf-8")
    FIELDS.write_text(python_fields(), encoding="utf-8")
    DOC.write_text(document(DOC.read_text(encoding="utf-8")), encoding="utf-8")
    print(f"wrote {HEADER}, {FIELDS} and the boundary table of {DOC}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
