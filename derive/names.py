"""The names and free text a spec may hold: one declared rule for each, checked before anything is derived.

A spec is data from a stranger. Its names become Python arguments, C locals,
C macros, file names and a module name; its free text (``title``, a
parameter's ``doc``, ``unit`` and ``valid``, body and element names) lands in
Python docstrings, C comments, Markdown and JSON. A name must therefore be a
plain ASCII identifier that none of those languages, libraries or the
generated code and runtime already use, and free text must be one line of a
small character set that cannot close a docstring or a comment. The templates
escape free text once more for each target language (:func:`escape_python_doc`,
:func:`escape_c_comment`, :func:`escape_markdown`): defence in depth, a no-op on
text that passed :func:`check_text`.
"""

from __future__ import annotations

import builtins
import keyword
import re
import sys
import unicodedata

#: A name: an ASCII letter, then ASCII letters, digits and ``_``; no leading ``_`` (Python's private and
#: dunder names, C's reserved ``__x`` and ``_X``).
NAME_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
#: Longest name: the derived names ``dd<q>`` and ``d<q>_plus`` and the C macros ``<MODEL>_P_<name>`` stay short.
MAX_NAME = 32
NAME_RULE = f"ASCII letters, digits and _, starting with a letter, at most {MAX_NAME} characters"

#: Python: keywords, soft keywords and builtins (``float``, ``abs``, ``type`` ...), read from the interpreter.
PYTHON_NAMES = frozenset(keyword.kwlist) | frozenset(getattr(keyword, "softkwlist", ())) | frozenset(dir(builtins))

#: C keywords of C99, and those C11 and C23 add without a leading underscore, and common extensions.
C_KEYWORDS = frozenset(
    "auto break case char const continue default do double else enum extern float for goto if inline int long "
    "register restrict return short signed sizeof static struct switch typedef union unsigned void volatile while "
    "alignas alignof bool false true nullptr static_assert thread_local typeof typeof_unqual constexpr "
    "asm fortran complex imaginary noreturn".split()
)

#: The C99 functions of <math.h> (each also with its ``f`` and ``l`` suffix below).
_MATH_FUNCTIONS = (
    "acos acosh asin asinh atan atan2 atanh cbrt ceil copysign cos cosh erf erfc exp exp2 expm1 fabs fdim floor "
    "fma fmax fmin fmod frexp hypot ilogb ldexp lgamma llrint llround log log10 log1p log2 logb lrint lround modf "
    "nan nearbyint nextafter nexttoward pow remainder remquo rint round scalbln scalbn sin sinh sqrt tan tanh "
    "tgamma trunc".split()
)
#: Names of the C library headers the generated code and the simulator include (<math.h>, <stdlib.h>, <string.h>,
#: <stddef.h>, <stdint.h>, <errno.h>): functions, macros and types, with the POSIX and glibc extras of <math.h>.
C_LIBRARY_NAMES = (
    frozenset(_MATH_FUNCTIONS)
    | frozenset(f + suffix for f in _MATH_FUNCTIONS for suffix in ("f", "l"))
    | frozenset(
        "INFINITY NAN HUGE_VAL HUGE_VALF HUGE_VALL FP_INFINITE FP_NAN FP_NORMAL FP_SUBNORMAL FP_ZERO FP_FAST_FMA "
        "FP_FAST_FMAF FP_FAST_FMAL FP_ILOGB0 FP_ILOGBNAN MATH_ERRNO MATH_ERREXCEPT math_errhandling fpclassify "
        "isfinite isinf isnan isnormal signbit isgreater isgreaterequal isless islessequal islessgreater "
        "isunordered float_t double_t "
        "M_E M_LOG2E M_LOG10E M_LN2 M_LN10 M_PI M_PI_2 M_PI_4 M_1_PI M_2_PI M_2_SQRTPI M_SQRT2 M_SQRT1_2 "
        "j0 j1 jn y0 y1 yn gamma drem finite significand signgam "
        "abort abs atexit at_quick_exit atof atoi atol atoll bsearch calloc div exit free getenv labs llabs ldiv "
        "lldiv malloc mblen mbstowcs mbtowc qsort quick_exit rand realloc srand strtod strtof strtol strtold "
        "strtoll strtoul strtoull system wcstombs wctomb aligned_alloc EXIT_FAILURE EXIT_SUCCESS MB_CUR_MAX NULL "
        "RAND_MAX div_t ldiv_t lldiv_t size_t wchar_t ptrdiff_t offsetof max_align_t memcpy memset memmove memcmp "
        "strlen errno EDOM ERANGE EILSEQ int8_t int16_t int32_t int64_t uint8_t uint16_t uint32_t uint64_t "
        "intptr_t uintptr_t DBL_EPSILON DBL_MAX DBL_MIN".split()
    )
)

#: Names the generated code and the derivation use themselves (derive/templates, rocking/sim/csrc/sim.c):
#: the C arguments ``s y ag agy p cst out``, the NumPy module's imports and globals, the generated functions,
#: the symbols of the derivation (``t``, ``x_g``, ``y_g``, the ground velocity ``vg``, EQUATIONS.md's left-hand sides)
#: and the expression constants.
GENERATED_NAMES = frozenset(
    "s on stop_on y ag agy pg p cst out t theta x_g y_g vg np numpy math scipy sympy "
    "NAME COORDINATES STATE PARAMETERS ARGUMENTS prepare prepared "
    "mass_matrix forcing rocking_accel contact_accel uplift impact energy power uplift_energy critical_angle "
    "critical_tangent E Edot E_uplift theta_cr u_s pi "
    "block_accelerations base_reaction element_forces a_top a_cm V_b N_b M_b Q".split()
)

#: Model names that would collide with a module or a file: the model's folder holds ``<name>.c``/``<name>.h``,
#: searched before the system headers (``-I``) when the simulator is compiled; ``model.py`` is imported.
FILE_NAMES = frozenset(getattr(sys, "stdlib_module_names", ())) | frozenset(
    "assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal stdalign stdarg "
    "stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath threads time uchar wchar wctype "
    "features alloca endian unistd sys bits gnu linux stdc "
    "sim boundary model manifest EQUATIONS numpy np scipy sympy rocking generated derive variants".split()
)

#: First parts (lower case) of the identifiers of the simulator's C sources (rocking/sim/csrc/*.c, *.h, comments
#: left out); tests/test_spec_security.py reads them again. A model's C names are ``<name>_...`` and ``<NAME>_...``,
#: so a model name among these could meet one of them.
RUNTIME_C_PREFIXES = frozenset(
    "a below case combine component constants contact critical dbl dense dopri dtheta early energy error ev event "
    "events g h half initial int32 int64 is last locate max min model n next ode omega pass peak phase phi pulse "
    "record result rk rms rocking run safe see seg settled simulate skip step sum t theta times uplift watched x y "
    "hist over rest segment stop velocity bumper gap sa sig sigint bound least stops verdict arcs at have kept "
    "memo pads regime gravity psi v vertical pad loaded always check first floor friction impact mu slide slip u "
    "uint32 corner e flight jump law lift ag any batch cos in lane lanes p scalar sin size stages tangential uint16 "
    "uint64 uintptr vector normal f lc lk lm ln2 load mask one pio2 shifter sincos store transpose trig best "
    "quartic".split()
)

#: Every reserved symbol name, with the reason a message gives; the first reason that applies wins.
_SYMBOL_RESERVED = (
    (GENERATED_NAMES, "a name of the generated code or the derivation"),
    (PYTHON_NAMES, "a Python keyword or builtin"),
    (C_KEYWORDS, "a C keyword"),
    (C_LIBRARY_NAMES, "a C library name (<math.h>, <stdlib.h>)"),
)


class SpecError(ValueError):
    """A model specification or a derivation option is invalid; the message names what and what is allowed."""


def quote(value, limit: int = 60) -> str:
    """``repr`` of ``value``, cut to ``limit`` characters: error messages stay one short line."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _ascii_identifier(name, what: str) -> str:
    """``name`` if it is a short ASCII identifier.

    Raises
    ------
    SpecError
        Naming ``what`` and the rule, and what Python would read a non-ASCII name as.
    """
    if not isinstance(name, str):
        raise SpecError(f"{what} must be a string, got {quote(name)}")
    if not name.isascii():
        # Python reads identifiers in NFKC: 'ℌ' is 'H', which could shadow another name unnoticed.
        folded = unicodedata.normalize("NFKC", name)
        raise SpecError(f"{what} {quote(name)} is not ASCII (Python would read it as {quote(folded)}); use {NAME_RULE}")
    if len(name) > MAX_NAME or not NAME_PATTERN.fullmatch(name):
        raise SpecError(f"{what} {quote(name)} is not a valid symbol name; use {NAME_RULE}")
    return name


def symbol_reason(name: str) -> str | None:
    """Why ``name`` cannot be a coordinate or parameter, or None if it can."""
    for names, reason in _SYMBOL_RESERVED:
        if name in names:
            return reason
    if re.fullmatch(r"cs[et]\d+", name):
        return "names cse<digits> and cst<digits> are the generated code's temporaries"
    lower = name.lower()
    for prefix in ("model_", "rocking_"):
        if lower.startswith(prefix):
            return f"names starting with {prefix!r} are the generated code's and the simulator's"
    return None


def check_symbol(name, model: str) -> str:
    """A coordinate or parameter name (or one derived from it), checked.

    Parameters
    ----------
    name
        The name as the spec gives it.
    model : str
        The model's name: ``<model>_`` starts the macros of the generated header.

    Raises
    ------
    SpecError
        When it is not an ASCII identifier or is reserved.
    """
    _ascii_identifier(name, "spec: symbol")
    reason = symbol_reason(name)
    if reason is None and name.lower().startswith(model.lower() + "_"):
        reason = f"names starting with '{model}_' are the model's C names"
    if reason is not None:
        raise SpecError(f"spec: {quote(name)} is reserved ({reason}); choose another name")
    return name


def check_model_name(name) -> str:
    """The model's name: folder, file and module name and C prefix, checked.

    Raises
    ------
    SpecError
        When it is not an ASCII identifier, or a file, module or C name of its own would collide.
    """
    if not (isinstance(name, str) and name.isascii() and len(name) <= MAX_NAME and NAME_PATTERN.fullmatch(name)):
        raise SpecError(f"spec: name must be an identifier, got {quote(name)} (use {NAME_RULE})")
    lower = name.lower()
    reason: str | None
    if name in FILE_NAMES or lower in {n.lower() for n in FILE_NAMES}:
        reason = "a module or file name the generated folder or the simulator's compilation would confuse it with"
    elif lower in RUNTIME_C_PREFIXES or lower.startswith(("rocking", "model")):
        reason = "its C names <name>_... could meet the simulator's"
    else:
        reason = symbol_reason(name)
    if reason is not None:
        raise SpecError(f"spec: model name {quote(name)} is reserved ({reason}); choose another name")
    return name


#: Free text: one line of printable ASCII without backslash, double quote or backtick (a Python string or
#: docstring, a Markdown code span), and without ``/*``, ``*/`` (a C comment) or ``??`` (a C trigraph).
#: The apostrophe is allowed: "the mass's" is common, and no target closes on it.
TEXT_PATTERN = re.compile(r"[A-Za-z0-9 .,;:!?()\[\]{}<>=+\-*/^_%&|~#@$']*")
_TEXT_FORBIDDEN = ("/*", "*/", "??")
TEXT_RULE = (
    "one line of ASCII letters, digits, spaces and .,;:!?()[]{}<>=+-*/^_%&|~#@$' "
    "(no backslash, double quote, backtick, /*, */ or ??)"
)
#: Longest text of each kind.
TEXT_LIMITS = {"title": 120, "doc": 200, "unit": 40, "valid": 40, "label": 64}


def check_text(value, what: str, kind: str) -> str:
    """A free-text entry of the spec, checked.

    Parameters
    ----------
    value
        The text as the spec gives it.
    what : str
        Where it is, for the message (``parameters.m doc``).
    kind : str
        A key of :data:`TEXT_LIMITS`.

    Raises
    ------
    SpecError
        When it is not a string, too long, or holds a character or sequence outside :data:`TEXT_RULE`.
    """
    if not isinstance(value, str):
        raise SpecError(f"{what} must be a string, got {quote(value)}")
    limit = TEXT_LIMITS[kind]
    if len(value) > limit:
        raise SpecError(f"{what} is {len(value)} characters long, at most {limit} allowed")
    if not TEXT_PATTERN.fullmatch(value) or any(bad in value for bad in _TEXT_FORBIDDEN):
        raise SpecError(f"{what} {quote(value)} is not allowed: free text is {TEXT_RULE}")
    return value


def _one_line(text: str) -> str:
    """``text`` with every control character (newlines included) turned into a space."""
    return "".join(" " if unicodedata.category(c)[0] == "C" else c for c in str(text))


def escape_python_doc(text) -> str:
    """``text`` safe inside a Python ``\"\"\"`` docstring: one line, no backslash escape, no closing quotes."""
    return _one_line(text).replace("\\", "\\\\").replace('"', '\\"')


def escape_c_comment(text) -> str:
    """``text`` safe inside a C ``/* */`` comment: one line, no comment delimiter, no trigraph."""
    out = _one_line(text)
    for bad, good in (("*/", "* /"), ("/*", "/ *"), ("??", "? ?"), ("\\", "/")):
        while bad in out:
            out = out.replace(bad, good)
    return out


def escape_markdown(text) -> str:
    """``text`` safe in Markdown prose: one line, no HTML, no code span or LaTeX delimiter breaking out."""
    out = _one_line(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return out.replace("`", "'").replace("\\", "/")
