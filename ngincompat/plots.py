"""Matplotlib figures in the style of the paper's profile panels (e.g. Fig. 1g)."""

from matplotlib.figure import Figure

from .io import atomic_path


def profile_pair(path, s, left, right, xlabel, title=None):
    """Two quantities against one coordinate, on two y axes (the paper's Fig. 1g).

    Parameters
    ----------
    path : path-like
        PNG file to write (atomically).
    s : array
        The coordinate.
    left, right : tuple (label, values)
        The quantity on the left and on the right axis.
    """
    fig = Figure(figsize=(5.0, 3.6), dpi=120)
    ax = fig.subplots()
    ax.plot(s, left[1], color="tab:blue", lw=2)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(left[0], color="tab:blue")
    ax.tick_params(axis="y", labelcolor="tab:blue")
    twin = ax.twinx()
    twin.plot(s, right[1], color="tab:red", lw=2, ls="--")
    twin.set_ylabel(right[0], color="tab:red")
    twin.tick_params(axis="y", labelcolor="tab:red")
    if title:
        ax.set_title(title)
    fig.tight_layout()
    _save(fig, path)


def profiles(path, s, curves, xlabel, ylabel, title=None):
    """Several curves against one coordinate on one axis; ``curves`` maps label -> values."""
    fig = Figure(figsize=(5.0, 3.6), dpi=120)
    ax = fig.subplots()
    for label, values in curves.items():
        ax.plot(s, values, lw=2, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend()
    if title:
        ax.set_title(title)
    fig.tight_layout()
    _save(fig, path)


def error_against_time(path, curves, title=None):
    """Error against run time on log-log axes; ``curves`` maps a label to (time, error) pairs."""
    fig = Figure(figsize=(5.0, 3.6), dpi=120)
    ax = fig.subplots()
    for label, pts in curves.items():
        ax.loglog([p[0] for p in pts], [max(p[1], 1e-16) for p in pts], marker="o", lw=2,
                  label=label)
    ax.set_xlabel("solve time [s]")
    ax.set_ylabel("relative error")
    ax.legend()
    if title:
        ax.set_title(title)
    fig.tight_layout()
    _save(fig, path)


def _save(fig, path):
    """Write the figure atomically. Figures are made without pyplot, so importing this module
    never changes matplotlib's backend (notebooks keep their inline figures)."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
