"""Parameter sweeps: ``ngincompat sweep run FILE.toml --out DIR`` and ``ngincompat sweep plot``.

A sweep runs one scene over a grid of parameters and collects chosen metrics into one table:

* :mod:`.spec`: the sweep file (TOML), its validation and its cases;
* :mod:`.runner`: running the cases (local processes, :mod:`ngincompat.studies.workers`, or
  Dask), resuming;
* :mod:`.table`: the table of a sweep (sweep.md/.csv/.json/.parquet), reading and plotting it.

From Python::

    from ngincompat.studies import sweep
    report = sweep.run_sweep(sweep.load_sweep("examples/sweeps/cube_poisson.toml"), "out")
    sweep.plot_sweep("out", "strain_energy", "nu", "energy.png", hue="order")
"""

from ngincompat.studies.sweep.runner import SweepReport, run_sweep
from ngincompat.studies.sweep.spec import Case, Sweep, load_sweep, parse_sweep
from ngincompat.studies.sweep.table import SweepTable, plot_sweep, read_table, sweep_figure
from ngincompat.studies.workers import run_case

__all__ = ["Case", "Sweep", "SweepReport", "SweepTable", "load_sweep",
           "parse_sweep", "plot_sweep", "read_table", "run_case", "run_sweep", "sweep_figure"]
