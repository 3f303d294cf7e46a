"""The FMU's ``documentation/index.html``, generated from the tables the FMU is registered from.

The variable tables come from the core (:data:`pipeplug.OUTPUTS`, :data:`pipeplug.PARAMETERS`,
:data:`pipeplug.OPTIONS`) and :mod:`pipeplug_fmu.fmi` (``INPUTS``); only the equations are text.
Used by :mod:`pipeplug_fmu.build` at build time; not shipped in the FMU.
"""
from __future__ import annotations

from html import escape

from pipeplug import OPTIONS, OUTPUTS, PARAMETERS, __version__
from pipeplug.interface import PROFILE_POINTS, PROFILES

from . import fmi

_EQUATIONS = """
<h2>Equations</h2>
<p>Coordinate x along the pipe axis from the struck end (x = 0) towards the soil; every force and
velocity is positive along +x. Sign(0) is the whole interval [-1, 1]: the static friction limit
equals the sliding limit, and a load exactly at the limit does not move a body.</p>
<pre>
P1 = 2 pi (R1 + h1)          outer perimeter of the pipe   [m]
P2 = 2 pi R1                 inner perimeter of the pipe   [m]
S1 = pi ((R1 + h1)^2 - R1^2) wall cross-section            [m2]
S2 = pi R1^2                 plug cross-section            [m2]
M1 = rho1 S1 L1              pipe mass                     [kg]
M2 = rho2 S2 L2              plug mass                     [kg]
</pre>
<h3>Model I (defaults): rigid pipe and plug, constant contact</h3>
<pre>
M1 U1'' = Q(t) + F_outer + F_inner,      M2 U2'' = -F_inner
F_outer in -P1 L1 tau1 Sign(U1')                      (soil on the pipe)
F_inner in -P2 L2 tau2 Sign(U1' - U2')                (plug on the pipe)
U1(0) = U2(0) = U1'(0) = U2'(0) = 0
</pre>
<p>Both contacts are solved jointly (nine stick/slip combinations, one solution). With tau2 = 0 or
L2 = 0 there is no plug and its outputs are 0. Outputs: v_pipe = U1', v_plug = U2',
u_pipe = U1, u_plug = U2, pipe_mode = sign(U1'), plug_mode = sign(U1' - U2'),
W_input = integral of Q U1' dt, W_friction = -integral of (F_outer U1' + F_inner (U1' - U2')) dt,
so that W_input = M1 U1'^2/2 + M2 U2'^2/2 + W_friction.</p>
<h3>Model II (<code>contact_growth = true</code>): outer contact grows with penetration</h3>
<pre>
F_outer in -P1 Lc tau1 Sign(U1'),   Lc = min(max(U1, 0), L1)
</pre>
<p>Everything else as in model I. Between events the pipe moves harmonically (sliding forward),
hyperbolically (sliding backward) or uniformly.</p>
<h3>Model III (<code>elastic = true</code>): elastic pipe and plug rods</h3>
<pre>
rho1 S1 d2u1/dt2 = E1 S1 d2u1/dx2 + f_outer(x, t) + f_inner(x, t),   0 &lt; x &lt; L1
rho2 S2 d2u2/dt2 = E2 S2 d2u2/dx2 - f_inner(x, t),                   L1 - L2 &lt; x &lt; L1
f_outer in -P1 tau1 Sign(du1/dt)            on the contact, x &gt;= L1 - Lc
f_inner in -P2 tau2 Sign(du1/dt - du2/dt)   on the plug, L1 - L2 &lt;= x &lt;= L1
E1 S1 du1/dx = -Q(t) at x = 0,   du1/dx = 0 at x = L1,   du2/dx = 0 at both plug ends
</pre>
<p>Lc = L1 (model I contact) or, with <code>contact_growth</code>, min(max(s, 0), L1) where s is
the displacement of the pipe's front end. The plug fills the front part of the pipe; pipe and plug
sections couple at equal reference coordinate x (small displacements). The rods are discretised
with spacing dx; the internal step is courant dx / c, c the fastest rod wave speed simulated
(sqrt(E1/rho1), and sqrt(E2/rho2) when the plug is simulated). The pipe outputs are taken at the
section x_monitor (linear interpolation between nodes), the plug outputs at the plug section
coupled to it (or the nearest plug section); the modes are those at x_monitor.</p>
<h3>Solvers of the rigid models</h3>
<p><code>solver = "exact"</code>: event-driven; the motion between friction events is closed form
and every event (stop, stick, breakaway, contact change) is located inside the step, so the outputs
are exact to round-off and do not depend on the communication grid.
<code>solver = "fd"</code>: the explicit scheme of the reference paper with both contacts solved
jointly, internal step at most dt.</p>
"""

_STEPPING = """
<h2>Stepping and statuses</h2>
<ul>
<li>Q is held constant over a communication step; outputs are values at the end of the step.</li>
<li>A step of length h takes n = ceil(h / h_max - 1e-9) equal internal steps (h_max = dt for
"fd", courant dx / c for the elastic model; "exact" needs none).</li>
<li>The FMU keeps its own time: a doStep whose communication point differs from it by more than
1e-9 max(1, |t|) is refused (fmi2Discard); within that tolerance the FMU adopts the host's time.
Stepping past the stopTime of fmi2SetupExperiment is refused with fmi2Error, as FMI 2.0
requires.</li>
<li>A non-finite Q, a step size that is not positive, or a step the model cannot take is refused
at doStep (fmi2Discard; nothing changes). A non-finite or out-of-range parameter (active or not),
a value the model cannot compute with, an unknown option value, a fixed parameter set after
initialization, a get or set of an unknown value reference, a String that is not UTF-8, a call
out of the FMI 2.0 call sequence, a NULL array or pointer, an FMU state that is not one of this
build, and a step whose outputs would not be finite are refused with fmi2Error; each refusal is
one log line naming the variable (or the call), its value and what is allowed, logged whether
debug logging is on or off. After an fmi2Error the instance accepts fmi2SetFMUstate, fmi2Reset,
fmi2Terminate and fmi2FreeInstance; every other call is refused with one short line
until fmi2Reset (or a state set), which makes it usable again; other instances are not
affected.</li>
<li>Every log line carries a category of the LogCategories in modelDescription.xml
(logStatusDiscard, logStatusError, ...); a <code>%</code> in logged text is written
<code>%%</code>, as hosts format log messages with printf.</li>
<li>fmi2Reset returns the instance to its state after instantiation. fmi2GetFMUstate,
fmi2SetFMUstate and the serialization functions save the whole internal state.</li>
</ul>
<h2>Host requirements</h2>
<p>PipePlug runs in a Python interpreter, with numpy. On linux64 the FMU's binary
(<code>binaries/linux64/PipePlug.so</code>, a small loader in front of the pythonfmu binary
<code>PipePlug_pythonfmu.so</code> beside it) finds one at the first fmi2Instantiate, in this
order:</p>
<ol>
<li>a Python already running in the host process (FMPy, libcosimpy and other Python-hosted
importers): that interpreter is used, never a second one, and it must have numpy;</li>
<li>else the Python named by the environment variable <code>PIPEPLUG_PYTHON</code>: the path of
its python executable, Python 3.10 or newer with numpy (a virtual environment's
<code>bin/python</code> works; its packages are used);</li>
<li>else <code>python3</code> on <code>PATH</code>, if it has numpy.</li>
</ol>
<p>Such a Python must have its shared library (libpython3.X.so), as most builds do. Its
interpreter is started in the host process (without its signal handlers) and stays until the
process ends. When no usable Python is found, fmi2Instantiate returns NULL after one log line
(category logStatusError) saying why and what to set; the host process goes on. Any host that
loads an FMU with dlopen can so run PipePlug: C and C++ importers need no LD_PRELOAD and no
PYTHONPATH. The resource location may be given in any spelling of a file URI
(<code>file:///p</code>, <code>file:/p</code>, <code>file://localhost/p</code>, with
percent-encoded characters); if it is not a file URI, the <code>resources</code> folder next to
<code>binaries</code> is used; a file URI of a folder without these resources, a malformed one, or
a NULL instance name makes fmi2Instantiate return NULL after one line. A python that does not
answer within 60 s (<code>PIPEPLUG_PYTHON_TIMEOUT</code> seconds) or prints more than 1 MiB when
asked is stopped and not used.</p>
<p>On win64 the binary is pythonfmu's own, unchanged: it needs a Python-hosted importer with
numpy; it refuses the same values and calls, but reports refusals as fmi2Fatal (with no category)
instead of fmi2Error, logs nothing with debug logging off, and has none of the linux64 loader's
checks of pointers, strings and resource locations. The win64 binary
is not run-tested by this project.</p>
<p>The FMU brings its own copy of the core and uses it even when the host has imported
another one. With numba installed, the elastic kernels are compiled (cached on disk under
<code>~/.cache/pipeplug</code> or <code>PIPEPLUG_CACHE_DIR</code>); without it, or with
<code>PIPEPLUG_NO_JIT=1</code>, they run as whole-array numpy with the same results, bit for bit.</p>
"""


def documentation_html(fmi_version: int = 2) -> str:
    """The whole ``index.html`` of the FMU of FMI ``fmi_version`` (2 or 3)."""
    parts = [f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
             f"<title>PipePlug {__version__}</title></head><body>",
             f"<h1>PipePlug {__version__}</h1>", f"<p>{escape(fmi.DESCRIPTION)}."
             f" FMI {fmi_version}.0 co-simulation, model identifier <code>PipePlug</code>.</p>",
             _EQUATIONS, "<h2>Variables</h2>", _input_table(), _output_table(),
             _parameter_table(), _option_table(), _STEPPING,
             *((fmi.fmi3_section("PipePlug"), _profile_table()) if fmi_version == 3 else ()),
             "</body></html>\n"]
    return "\n".join(parts)


def _profile_table() -> str:
    """The FMI 3.0 profile arrays, sized by the structural parameter profile_points."""
    low, high = PROFILE_POINTS[1:]
    return table(f"Array outputs (FMI 3.0): profile_points elements each (structural parameter, "
                 f"UInt64, default {PROFILE_POINTS[0]}, {low} to {high}; set it before "
                 f"fmi3EnterInitializationMode); element k is the scalar output with x_monitor "
                 f"at its section", ("name", "unit", "meaning"),
                 [(p.name, p.unit, p.meaning) for p in PROFILES])


def table(caption: str, header: tuple, rows) -> str:
    """An HTML table (also Hammer.fmu's documentation's)."""
    head = "".join(f"<th>{escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{escape(str(c))}</td>" for c in row) + "</tr>\n"
                   for row in rows)
    return (f"<table border=\"1\" cellpadding=\"3\"><caption>{escape(caption)}</caption>\n"
            f"<tr>{head}</tr>\n{body}</table>")


def _input_table() -> str:
    rows = [(name, unit or "-", kind, start, meaning)
            for name, kind, unit, start, meaning in fmi.INPUTS]
    return table("Inputs (Real continuous, Integer discrete)",
                 ("name", "unit", "type", "start", "meaning"), rows)


def _output_table() -> str:
    rows = [(o.name, o.unit if o.kind == "Real" else "-",
             o.kind if o.kind == "Real" else "Integer (-1, 0, 1)", o.meaning) for o in OUTPUTS]
    return table("Outputs (initial exact, start 0; values at the end of each step)",
                  ("name", "unit", "type", "meaning"), rows)


def _parameter_table() -> str:
    rows = [(p.name, p.unit, f"{p.default:g}", p.allowed() + _active(p), p.description)
            for p in PARAMETERS]
    return table("Parameters (Real, fixed)", ("name", "unit", "default", "allowed", "meaning"),
                  rows)


_GROUPS = {"elastic": "elastic = true", "fd": 'solver = "fd"'}


def _active(p) -> str:
    return "" if p.active_with is None else f" (checked only with {_GROUPS[p.active_with]})"


def _option_table() -> str:
    rows = [(name, "Boolean" if isinstance(default, bool) else "String", _fmi_text(default),
             ", ".join(map(_fmi_text, allowed)), meaning)
            for name, (allowed, default, meaning) in OPTIONS.items()]
    return table("Options (fixed parameters)", ("name", "type", "default", "allowed",
                                                 "meaning"), rows)


def _fmi_text(value) -> str:
    """A Boolean or String value as written in FMI (``true``, ``"exact"``)."""
    return str(value).lower() if isinstance(value, bool) else f'"{value}"'
