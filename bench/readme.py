"""The README's measured figures, written from the files the bench commands wrote, never typed.

``python bench/readme.py`` rewrites each block of README.md between its markers (:func:`markers`) from its
file (:data:`BLOCKS`): the speed figures of the last `make bench` (bench/last.json), the adaptive maps
against full ones (bench/adaptive-400.json, bench/adaptive-1000.json), what each pair of an adaptive map's steps
saves and misses (bench/adaptive-steps.json), the 400 x 400 map from the command line (bench/cli-400.json), each
written by the command it names.
tests/test_readme.py fails when a block and its file differ, so a figure in the README is always the one a
run measured, with its date, machine and load.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from adaptive import table
from adaptive_filament import table as filament_table
from adaptive_spectrum import table as spectrum_table
from adaptive_steps import table as steps_table
from cli_map import files_line, targets_line
from cli_map import table as cli_table

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"


def render(results: dict) -> str:
    """The README's speed table and its sentences, from the figures of one bench run."""
    m, sim, st, stops = results["machine"], results["simulator"], results["studies"], results["stops"]
    side = st["n_memory"]
    row = (
        f"| {m['date']} | {sim['c_responses_per_s_per_core']:,.0f} | {sim['numpy_ms_per_response']:.0f} ms | "
        f"{sim['speedup_c_vs_baseline']:,.0f}x | {st['map_speedup_2_vs_1']:.2f}x | "
        f"{st[f'map_{side}x{side}_peak_rss_mb']:.0f} MB | {st['demo_seconds']:.1f} s |"
    )
    lines = [
        f"The last `make bench`: {m['date']}, {m['cpu']}, {m['cores']} cores, load average "
        f"{m['load_average_1min']:.1f} at its start and {m['load_average_1min_after']:.1f} at its end, "
        f"Python {m['python']}.",
        "",
        f"| run | C path, responses/s/core | NumPy path | C / baseline | 2 workers / 1 | "
        f"{side} x {side} map memory | demo |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        row,
        "",
    ]
    if "instructions" in results:
        counted = results["instructions"]
        text = (
            f"Instructions per response of the C path on the bench map under callgrind: "
            f"{counted['instructions_per_response']:,.0f}"
        )
        part = counted.get("by_part")
        if part:
            fixed = sum(v for k, v in part.items() if k.startswith("libm")) + part["generated model"]
            text += (
                f": libm's sin and cos {part['libm sin and cos']:,.0f}, its pow {part['libm pow']:,.0f}, the "
                f"generated model's functions {part['generated model']:,.0f} (together, with libm's other calls, "
                f"{fixed:,.0f}: what no change of sim.c that keeps every result bit for bit can remove), the "
                f"integrator (sim.c) {part['integrator (sim.c)']:,.0f}"
            )
        lines.append(text + ".")
    if "c_lanes" in sim:
        width = sim["c_lanes"]
        lanes = f"in lanes of {width} doubles per vector" if width else "scalar (no lanes)"
        text = (
            f"The C path ran {lanes} (CPU: {', '.join(m.get('cpu_vector_flags', [])) or 'no vector flags read'}): "
            f"{sim['c_scalar_over_lanes_cpu']:.2f}x fewer CPU seconds per response than its scalar path"
        )
        if "instructions_lanes" in results:
            counted = results["instructions_lanes"]
            text += (
                f"; {counted['instructions_per_response']:,.0f} instructions per response in lanes of "
                f"{counted['lanes']} (callgrind runs no AVX-512)"
            )
        lines.append(text + ".")
    lines += [
        f"End stops at the block's edges (`Stops.at_edges`) cost {stops['stops_over_free_time']:.2f}x the CPU time "
        f"per response of the unlimited damper on the same map in lanes, "
        f"{stops['stops_over_free_time_scalar']:.2f}x on the scalar path (medians of 3 paired "
        f"runs), with {stops['stop_contacts_per_response']:.1f} contacts per response. `rocking threshold` on its "
        f"default grid "
        f"takes {st['threshold_seconds']:.1f} s on 2 workers; a fragility of 1,000 stochastic motions x 4 levels x "
        f"2 directions x 2 parts {st['fragility_1000_seconds']:.0f} s.",
    ]
    if "split_map" in st:
        sm, sf = st["split_map"], st["split_fragility"]
        lines.append(
            f"On one worker (bench/split.py, imports excluded), the {st['n_map']} x {st['n_map']} map spends "
            f"{100 * sm['c_s'] / sm['cpu_s']:.0f} % of its CPU in C and {100 * sm['other_fraction']:.0f} % in the "
            f"Python around it; a fragility of {sf['n']} stochastic motions {100 * sf['c_s'] / sf['cpu_s']:.0f} % in "
            f"C, {100 * sf['motions_s'] / sf['cpu_s']:.0f} % drawing its motions and "
            f"{100 * sf['other_fraction']:.0f} % in Python (tiles, the lognormal fits and their bootstrap)."
        )
    return "\n".join(lines)


def measured_by(results: dict) -> str:
    """The sentence that says which command measured a table, when and where."""
    m = results["machine"]
    # Files without the load at the end recorded the load once, when they were written.
    load = (
        f"{m['load_average_1min']:.1f} at its start and {m['load_average_1min_after']:.1f} at its end"
        if "load_average_1min_after" in m
        else f"{m['load_average_1min']:.1f}"
    )
    return (
        f"Measured by `{results['command']}` ({m['date']}, {m['cpu']}, {m['cores']} cores, load average "
        f"{load}; a shared machine, so the wall times vary by 2x from run to run, the responses and the classes "
        "do not):"
    )


def render_adaptive(results: dict) -> str:
    """The table of adaptive maps against full ones, and the command and machine that measured it."""
    return f"{measured_by(results)}\n\n{table(results['maps'])}"


def render_adaptive_spectrum(result: dict) -> str:
    """The table of what an exact beta scan must compute against the full scans, and the command and machine that
    measured it."""
    return f"{measured_by(result)}\n\n{spectrum_table(result)}"


def render_adaptive_filament(result: dict) -> str:
    """The map of issue 35, adaptive against full, and the command and machine that measured it."""
    return f"{measured_by(result)}\n\n{filament_table(result)}"


def render_adaptive_steps(result: dict) -> str:
    """Each pair of an adaptive map's steps over the bench's maps, and the command and machine that measured it."""
    return f"{measured_by(result)}\n\n{steps_table(result['maps'])}"


def render_cli(results: dict) -> str:
    """The command line's maps against their simulations, each file's time and the targets, and the command and
    machine that measured them."""
    return f"{measured_by(results)}\n\n{cli_table(results)}\n\n{files_line(results)}\n\n{targets_line(results)}"


#: Each block of the README written here: its name, its file, and how it is rendered.
BLOCKS = {
    "speed": ("bench/last.json", render),
    "adaptive-400": ("bench/adaptive-400.json", render_adaptive),
    "adaptive-1000": ("bench/adaptive-1000.json", render_adaptive),
    "cli-400": ("bench/cli-400.json", render_cli),
    "adaptive-spectrum": ("bench/adaptive-spectrum.json", render_adaptive_spectrum),
    "adaptive-filament": ("bench/adaptive-filament.json", render_adaptive_filament),
    "adaptive-steps": ("bench/adaptive-steps.json", render_adaptive_steps),
}


def markers(name: str) -> tuple[str, str]:
    """The comments around the block ``name`` in the README."""
    return f"<!-- {name}: written by bench/readme.py from {BLOCKS[name][0]} -->", f"<!-- /{name} -->"


def block(text: str, name: str = "speed") -> str:
    """The part of ``text`` between the markers of block ``name``, without them."""
    start, end = markers(name)
    return text.split(start, 1)[1].split(end, 1)[0].strip("\n")


def fresh(name: str) -> str:
    """The block ``name`` rendered from its file."""
    path, rendering = BLOCKS[name]
    return rendering(json.loads((ROOT / path).read_text()))


def main() -> int:
    text = README.read_text()
    for name, (path, _) in BLOCKS.items():
        start, end = markers(name)
        head, rest = text.split(start, 1)
        text = f"{head}{start}\n{fresh(name)}\n{end}{rest.split(end, 1)[1]}"
        print(f"README.md: the figures of {path}")
    README.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
