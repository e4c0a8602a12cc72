"""Figure of a time history: theta/alpha, the damper's stroke and the ground acceleration."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_responses(responses: dict, alpha: float, path: str | Path, title: str = "") -> Path:
    """Draw recorded responses on shared axes and save the figure.

    Parameters
    ----------
    responses : dict of str to Response
        Label to a response run with ``record=True``.
    alpha : float
        Slenderness angle of the block [rad], to show ``theta / alpha``.
    path : str or Path
        Output file; its suffix picks the format (PNG, PDF, SVG).
    title : str
        Figure title.
    """
    fig, (ax_th, ax_x, ax_g) = plt.subplots(3, 1, sharex=True, figsize=(8, 7), constrained_layout=True)
    for label, r in responses.items():
        h = r.history
        if h is None:
            raise ValueError(f"response {label!r} was not recorded (record=True)")
        (line,) = ax_th.plot(h["t"], h["theta"] / alpha, label=label)
        if "x" in h:
            ax_x.plot(h["t"], h["x"], color=line.get_color(), label=label)
        ax_g.plot(h["t"], h["ag"], color=line.get_color(), label=label)
        if r.overturned:
            ax_th.axvline(r.t_overturn, color=line.get_color(), ls=":", lw=1)
    for y in (-1, 1):
        ax_th.axhline(y, color="0.6", lw=0.8, ls="--")
    ax_th.set_ylabel(r"$\theta / \alpha$")
    ax_x.set_ylabel("damper stroke x [m]")
    ax_g.set_ylabel(r"$\ddot{x}_g$ [m/s$^2$]")
    ax_g.set_xlabel("t [s]")
    ax_th.legend(loc="best")
    if title:
        fig.suptitle(title)
    for ax in (ax_th, ax_x, ax_g):
        ax.grid(True, alpha=0.3)
    ax_th.set_ylim(
        max(ax_th.get_ylim()[0], -np.pi / 2 / alpha * 1.05), min(ax_th.get_ylim()[1], np.pi / 2 / alpha * 1.05)
    )
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
