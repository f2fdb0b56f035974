"""ngincompat.scenes.metrics: every metric declared once, with a unit and a meaning, and every
name a study or a check reads declared by a scene."""

import re
from pathlib import Path

import pytest

from ngincompat.scenes import SCENES
from ngincompat.scenes.metrics import (
    CURVATURE,
    INCOMPATIBILITY,
    MECHANICS,
    Metric,
    registry,
    select,
)
from ngincompat.studies.costs import ACCURACY_METRIC

ROOT = Path(__file__).resolve().parents[2]

#: A metric's name read as a literal key: ``metrics["name"]``, ``metrics.get("name"``.
READ = re.compile(r'metrics(?:\[|\.get\()\s*"(\w+)"')


def test_registry_keeps_the_order_of_its_parts_and_is_read_only():
    a = Metric("first")
    merged = registry(MECHANICS, extra=a)
    assert list(merged) == [*MECHANICS, "extra"] and merged["extra"] is a
    with pytest.raises(TypeError):
        merged["other"] = a


def test_registry_refuses_a_name_declared_twice():
    with pytest.raises(ValueError, match="declared twice: strain_energy"):
        registry(MECHANICS, strain_energy=Metric("again", "energy"))


def test_select_takes_each_name_from_the_first_source_that_has_it():
    other = {"strain_energy": Metric("other", "energy"), "x": Metric("x")}
    chosen = select(["x", "strain_energy"], MECHANICS, other)
    assert list(chosen) == ["x", "strain_energy"]
    assert chosen["strain_energy"] is MECHANICS["strain_energy"]
    with pytest.raises(StopIteration):
        select(["nowhere"], MECHANICS)


@pytest.mark.parametrize("name", list(SCENES))
def test_every_metric_has_a_meaning_and_a_unit_in_the_scenes_units(name):
    cls = SCENES[name]
    quantities = set(cls.units)
    for metric, declared in cls.metrics.items():
        assert isinstance(declared, Metric), (name, metric)
        assert len(declared.meaning.split()) >= 4, (name, metric)
        unit = cls.metric_unit(metric)
        words = set(re.findall(r"[a-z]+", declared.quantity))
        assert words <= quantities, (name, metric, words - quantities)
        # spelled in the scene's units: no quantity word is left in it
        assert not set(re.findall(r"[a-z]+", unit)) & (quantities - set(cls.units.values()))
    with pytest.raises(KeyError):
        cls.metric_unit("no_such_metric")


def test_shared_declarations_are_reused_not_written_again():
    """A scene reports a shared name with the shared declaration, or with one of another
    quantity (folding's plane section: its strain energy per unit depth)."""
    for cls in SCENES.values():
        for shared in (MECHANICS, INCOMPATIBILITY, CURVATURE):
            for metric in set(shared) & set(cls.metrics):
                own = cls.metrics[metric]
                assert own is shared[metric] or own.quantity != shared[metric].quantity, (
                    cls.name, metric)


def test_every_metric_a_module_reads_by_name_is_declared_by_a_scene():
    declared = {m for cls in SCENES.values() for m in cls.metrics}
    read = {}
    for path in sorted((ROOT / "ngincompat").rglob("*.py")):
        for name in READ.findall(path.read_text()):
            read.setdefault(name, path.relative_to(ROOT).as_posix())
    assert len(read) > 30                       # the studies' findings read dozens
    assert {n: p for n, p in read.items() if n not in declared} == {}


def test_the_indicators_and_the_cost_study_read_their_scenes_metrics():
    for name, cls in SCENES.items():
        assert {i.metric for i in cls.indicators} <= set(cls.metrics), name
        assert ACCURACY_METRIC[name] in cls.metrics, name
