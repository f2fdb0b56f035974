"""Side by side with a peer code: ``ngincompat bench peer``.

The peer is FEniCSx (DOLFINx 0.5.2) solving the same cube of section 3.1 (theta = 1 + X1 t / 4,
neo-Hookean mu = 0.55 MPa, nu = 0.4, traction-free, full cube) with its own script
``fenicsx_growth.py``, run from the peer's folder after sourcing its ``env_dolfinx.sh`` (the
set-up that unpacks the Debian packages without root is the peer's own). Nothing of the peer
is imported or copied: it runs as a separate process and reports one line
``RESULT {json}`` with its strain energy ``W`` and its solve time ``t_solve`` (Newton with
assembly and factorisations; imports and set-up excluded).

The benchmark runs the peer and ``ngincompat run cube`` alternately, each in a fresh process
of the same process tree, ``pairs`` times, so that both see the same load of the machine.
Ours is timed like the peer: the growth stage (predictor, assemblies, factorisations, Newton),
without meshing, set-up and post-processing. Each pair gives the ratio of the peer's solve
time to ours; both energy errors are against :data:`~ngincompat.studies.bench.CUBE_ENERGY`. The
comparison counts only where our energy error is at most the peer's.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ngincompat.errors import ParameterError
from ngincompat.studies.bench import CUBE_ENERGY, UNITS
from ngincompat.workflow import tables

#: Environment variable naming the peer's folder (``env_dolfinx.sh``, ``fenicsx_growth.py``).
PEER_VARIABLE = "NGINCOMPAT_PEER"
#: The peer's script and environment, inside its folder.
PEER_SCRIPT, PEER_ENV = "fenicsx_growth.py", "env_dolfinx.sh"
#: The peer's reference point of issue 15: P4 tetrahedra on 4 x 4 x 4 x 6 cells (14.7k dofs).
PEER_ARGS = ("--N", "4", "--degree", "4")
#: Columns of the table, one row per run.
COLUMNS = ("pair", "code", "setting", "ndof", "newton", "solve_s", "strain_energy",
           "energy_error", "load")
#: Columns of the summary table (``peer_ratio``): the median ratio, its range over the
#: pairs, the largest energy errors, the range of the load averages.
RATIO_COLUMNS = ("ours", "pairs", "ratio", "ratio_min", "ratio_max", "our_error",
                 "peer_error", "equal_or_better", "load")


def peer_folder(folder: str | os.PathLike | None = None) -> Path:
    """The peer's folder: ``folder``, else $NGINCOMPAT_PEER.

    Raises
    ------
    ParameterError
        Neither is given, or the folder lacks the script, its environment or the unpacked
        FEniCSx (``debroot``): one line saying how to set the peer up.
    """
    given = folder or os.environ.get(PEER_VARIABLE)
    how = ("set it up once as described in its README (setup_fenicsx_debroot.sh unpacks "
           "FEniCSx without root), then pass --peer DIR or set " + PEER_VARIABLE)
    if not given:
        raise ParameterError(f"the FEniCSx peer is not installed: no --peer folder and no "
                             f"${PEER_VARIABLE}; {how}")
    path = Path(given).expanduser()
    missing = [name for name in (PEER_SCRIPT, PEER_ENV, "debroot")
               if not (path / name).exists()]
    if missing:
        raise ParameterError(f"the FEniCSx peer is not installed in {path} (missing "
                             f"{', '.join(missing)}); {how}")
    return path


def run_peer(folder: Path, args: Sequence[str] = PEER_ARGS, timeout: float = 1800) -> dict:
    """Run the peer's script once from its folder; returns its RESULT record.

    Raises
    ------
    RuntimeError
        The peer failed or printed no RESULT line (its last output is in the message).
    """
    command = (f'source ./{PEER_ENV} && exec "$PY" {PEER_SCRIPT} '
               + " ".join(args) + " --quiet")
    done = subprocess.run(["bash", "-c", command], cwd=folder, capture_output=True,
                          text=True, timeout=timeout,
                          env={**os.environ, "PEER": str(folder)})
    for line in done.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[len("RESULT "):])
    raise RuntimeError(f"the peer failed (exit {done.returncode}): "
                       f"{(done.stderr or done.stdout).strip()[-500:]}")


def run_ours(settings: dict, timeout: float = 1800) -> dict:
    """Run ``ngincompat run cube`` with ``settings`` in a fresh process; returns results.json.

    Raises
    ------
    RuntimeError
        The run failed (its error output is in the message).
    """
    with tempfile.TemporaryDirectory(prefix="ngincompat-peer-") as tmp:
        sets = [f"--set={k}={v}" for k, v in {"outputs": "none", **settings}.items()]
        done = subprocess.run([sys.executable, "-m", "ngincompat.cli", "run", "cube", "--out",
                               tmp, "-q", *sets], capture_output=True, text=True,
                              timeout=timeout, cwd=Path(__file__).resolve().parents[1])
        if done.returncode != 0:
            raise RuntimeError(f"ngincompat run cube failed (exit {done.returncode}): "
                               f"{done.stderr.strip()[-500:]}")
        return json.loads((Path(tmp) / "results.json").read_text())


def energy_error(energy: float) -> float:
    """|W - CUBE_ENERGY| / CUBE_ENERGY."""
    return abs(energy - CUBE_ENERGY) / CUBE_ENERGY


def compare(folder: str | os.PathLike | None = None, settings: Mapping[str, Any] | None = None,
            pairs: int = 3, peer_args: Sequence[str] = PEER_ARGS
            ) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Run the peer and our cube alternately ``pairs`` times.

    Parameters
    ----------
    folder : path-like, optional
        The peer's folder (default: $NGINCOMPAT_PEER); see :func:`peer_folder`.
    settings : dict, optional
        Settings of our cube scene (``--set``); default: the scene's defaults.
    pairs : int
        Number of (peer, ours) pairs, >= 1.
    peer_args : sequence of str
        Arguments of the peer's script (default :data:`PEER_ARGS`).

    Returns
    -------
    rows : list of dict
        One row per run, columns :data:`COLUMNS` (``load``: the machine's 1-minute load
        average at the run's start).
    summary : dict
        ``ratios`` (peer solve time over ours, per pair), ``ratio`` (their median),
        ``peer_error`` and ``our_error`` (largest energy errors over the pairs) and
        ``equal_or_better`` (our largest error at most the peer's smallest).
    """
    if pairs < 1:
        raise ParameterError(f"pairs = {pairs} must be >= 1")
    path = peer_folder(folder)
    settings = dict(settings or {})
    ours_label = ", ".join(f"{k}={v}" for k, v in settings.items()) or "defaults"
    rows, ratios = [], []
    for pair in range(1, pairs + 1):
        peer_load = os.getloadavg()[0]
        peer = run_peer(path, peer_args)
        our_load = os.getloadavg()[0]
        ours = run_ours(settings)
        p = ours["params"]
        solve = sum(ours["timings"].get(stage, 0.0) for stage in ours["solver"])
        rows.append({"pair": pair, "code": f"FEniCSx {peer.get('version', '')}".strip(),
                     "setting": f"{peer['cell']} P{peer['degree']}, N={peer['N']}, "
                                f"{peer['solver']}",
                     "ndof": peer["dofs"], "newton": peer["newton_its"],
                     "solve_s": peer["t_solve"], "strain_energy": peer["W"],
                     "energy_error": energy_error(peer["W"]), "load": round(peer_load, 1)})
        rows.append({"pair": pair, "code": "ngincompat",
                     "setting": f"{p['elements']} order {p['order']}, maxh {p['maxh']:g}, "
                                f"{p['model']}",
                     "ndof": ours["mesh"]["ndof"],
                     "newton": sum(h["newton_iterations"] for h in ours["solver"].values()),
                     "solve_s": solve, "strain_energy": ours["metrics"]["strain_energy"],
                     "energy_error": energy_error(ours["metrics"]["strain_energy"]),
                     "load": round(our_load, 1)})
        ratios.append(peer["t_solve"] / solve)
    peer_errors = [r["energy_error"] for r in rows if r["code"] != "ngincompat"]
    our_errors = [r["energy_error"] for r in rows if r["code"] == "ngincompat"]
    summary = {"ratios": ratios, "ratio": statistics.median(ratios),
               "peer_error": max(peer_errors), "our_error": max(our_errors),
               "equal_or_better": max(our_errors) <= min(peer_errors), "ours": ours_label}
    return rows, summary


def main(folder: str | os.PathLike | None = None, settings: Mapping[str, Any] | None = None,
         pairs: int = 3, out: str | os.PathLike | None = None) -> list[str]:
    """``ngincompat bench peer``: :func:`compare`; returns the lines to print (with ``out``
    the table is also written as ``peer.md``, ``.csv``, ``.json``, and its summary, one row
    with :data:`RATIO_COLUMNS`, as ``peer_ratio``)."""
    rows, summary = compare(folder, settings, pairs)
    units = {**UNITS, "solve_s": "s"}
    verdict = ("at equal or better energy error" if summary["equal_or_better"] else
               "BUT our energy error is larger than the peer's: not a like-for-like ratio")
    loads = [r["load"] for r in rows]
    ratio_row = {"ours": summary["ours"], "pairs": len(summary["ratios"]),
                 "ratio": summary["ratio"], "ratio_min": min(summary["ratios"]),
                 "ratio_max": max(summary["ratios"]), "our_error": summary["our_error"],
                 "peer_error": summary["peer_error"],
                 "equal_or_better": summary["equal_or_better"],
                 "load": f"{min(loads):g}-{max(loads):g}"}
    lines = [tables.markdown(rows, list(COLUMNS), units), "",
             f"solve-time ratio FEniCSx / ngincompat ({summary['ours']}): "
             f"{summary['ratio']:.2f} (median of "
             + ", ".join(f"{r:.2f}" for r in summary["ratios"]) + f") {verdict}: energy "
             f"errors {summary['our_error']:.2g} (ours) and {summary['peer_error']:.2g} "
             f"(peer) against W = {CUBE_ENERGY:.7g} N mm"]
    if out is not None:
        tables.write(out, "peer", rows, list(COLUMNS), units, reference_energy=CUBE_ENERGY,
                     **summary)
        tables.write(out, "peer_ratio", [ratio_row], list(RATIO_COLUMNS),
                     {"our_error": "-", "peer_error": "-"}, reference_energy=CUBE_ENERGY)
        lines.append(f"tables written to {Path(out) / 'peer.md'} and peer_ratio.md "
                     "(.csv, .json)")
    return lines
