"""The README's speed figures, written from the last `make bench` (bench/last.json), never typed.

``python bench/readme.py`` rewrites the part of README.md between the markers :data:`START` and
:data:`END` from bench/last.json; tests/test_readme.py fails when the two differ, so a figure in
the README is always the one the last bench run measured, with its date, machine and load.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LAST = ROOT / "bench" / "last.json"
README = ROOT / "README.md"
START = "<!-- speed: written by bench/readme.py from bench/last.json -->"
END = "<!-- /speed -->"


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
        lines.append(
            f"Instructions per response of the C path on the bench map under callgrind: "
            f"{results['instructions']['instructions_per_response']:,.0f}."
        )
    lines += [
        f"End stops at the block's edges (`Stops.at_edges`) cost {stops['stops_over_free_time']:.2f}x the time "
        f"per response of the unlimited damper on the same map (median of 3 paired runs), with "
        f"{stops['stop_contacts_per_response']:.1f} contacts per response. `rocking threshold` on its default grid "
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


def block(text: str) -> str:
    """The part of ``text`` between the markers, without them."""
    return text.split(START, 1)[1].split(END, 1)[0].strip("\n")


def main() -> int:
    text = README.read_text()
    fresh = render(json.loads(LAST.read_text()))
    head, rest = text.split(START, 1)
    README.write_text(f"{head}{START}\n{fresh}\n{END}{rest.split(END, 1)[1]}")
    print(f"README.md: the speed figures of {LAST.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
