"""The names the program knows are written once (ngincompat.names)."""

import re
from pathlib import Path

import pytest

from ngincompat import names

ROOT = Path(__file__).resolve().parents[2]


def test_the_scene_classes_are_registered_under_the_names_in_their_order():
    from ngincompat.scenes import SCENES
    assert tuple(SCENES) == names.SCENES
    assert all(cls.name == name for name, cls in SCENES.items())


@pytest.mark.parametrize("listed", [names.SCENES, names.AXONS, names.FOOTPRINTS])
def test_no_module_writes_a_name_list_out_again(listed):
    """Two neighbours of a list written as literals in a sequence (``"curved", "concentric"``)
    anywhere but in :mod:`ngincompat.names` is a copy that can drift."""
    pair = re.compile(rf'["\']{listed[0]}["\'],\s*["\']{listed[1]}["\']')
    copies = [str(p.relative_to(ROOT)) for package in ("ngincompat", "geometries")
              for p in sorted((ROOT / package).rglob("*.py"))
              if p.name != "names.py" and pair.search(p.read_text())]
    assert copies == []


def test_the_lists_are_distinct_names():
    for listed in (names.SCENES, names.AXONS, names.FOOTPRINTS):
        assert len(set(listed)) == len(listed) and all(re.fullmatch(r"[a-z]+", n)
                                                      for n in listed)
