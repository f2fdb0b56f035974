"""Scene parameters: types, ranges and units declared once, one converter for --set strings,
TOML values and Python keyword arguments, tuples and outputs as real types."""

import math
import tomllib

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ngincompat.cli import OUTPUT_NAMES, _outputs
from ngincompat.errors import ParameterError
from ngincompat.parameters import OUTPUTS, Outputs, Param, Range, _Floats, param
from ngincompat.scenes import SCENES, AtrophyScene, CubeScene, DiscScene, SkinExpansionScene
from ngincompat.scenes.base import Scene
from ngincompat.scenes.material import K1, K2, KAPPA, MU, NU
from ngincompat.studies.sweep import load_sweep, parse_sweep
from ngincompat.workflow import output
from ngincompat.workflow.results import Results


def _outside(p):
    """Values of parameter ``p`` outside its declared type or range (none for free text)."""
    kind = type(p.kind).__name__
    values = []
    rng = getattr(p.kind, "range", None)
    if kind in ("_Float", "_Int"):
        if rng is not None:
            number = int if kind == "_Int" else float
            if rng.low is not None:
                values.append(number(rng.low if rng.low_open else rng.low - 1))
            if rng.high is not None:
                values.append(number(rng.high if rng.high_open else rng.high + 1))
        if kind == "_Float":
            values += [math.nan, math.inf]
        values.append("two")
    elif kind == "_Bool":
        values += ["maybe", 2]
    elif kind in ("_Choice", "_Outputs"):
        values += ["no-such-choice"]
    elif kind == "_Floats":
        if p.kind.length:
            values.append(",".join(["1"] * (p.kind.length + 1)))
        if rng is not None and rng.low is not None:
            values.append(tuple([rng.low if rng.low_open else rng.low - 1.0]
                                * (p.kind.length or 1)))
        values.append("a,b")
    elif kind == "_WordsOrFloats":
        values += ["nowhere", (1.0, 2.0)]
    return values


BAD = [(name, key, value) for name, cls in SCENES.items()
       for key, p in cls.declarations().items() for value in _outside(p)]


@pytest.mark.parametrize("scene, key, value", BAD, ids=[f"{s}-{k}-{v!r}" for s, k, v in BAD])
def test_every_parameter_rejects_a_value_outside_its_range_naming_it(scene, key, value):
    """A Python keyword argument and the --set string of the same value are both refused, in
    one line that names the parameter and its allowed range."""
    cls = SCENES[scene]
    allowed = cls.declarations()[key].allowed()
    for given_as in (value, str(value) if not isinstance(value, tuple)
                     else ",".join(map(str, value))):
        with pytest.raises(ParameterError, match=f"^{key} = ") as info:
            cls.from_settings({key: given_as})
        message = str(info.value)
        assert message.endswith(f"allowed {allowed}") and "\n" not in message, message


def test_the_table_of_bad_values_covers_every_kind_of_parameter():
    kinds = {type(p.kind).__name__ for cls in SCENES.values() for p in cls.declarations().values()}
    assert {"_Float", "_Int", "_Bool", "_Choice", "_Outputs", "_Floats",
            "_WordsOrFloats"} <= kinds
    assert len(BAD) > 300


@pytest.mark.parametrize("name", SCENES)
def test_defaults_are_valid_and_convert_to_themselves(name):
    cls = SCENES[name]
    scene = cls()
    for key, p in cls.declarations().items():
        assert p.convert(p.default) == p.default == getattr(scene, key), key
        assert p.convert(p.to_json(p.default)) == p.default, key


@pytest.mark.parametrize("name", SCENES)
def test_discretisation_parameters_keep_their_ranges_in_every_scene(name):
    """A scene that changes the default of order, maxh, steps or g_order keeps the range of
    the base declaration."""
    declared = SCENES[name].declarations()
    base = Scene.declarations()
    for key in ("order", "maxh", "steps", "g_order"):
        assert declared[key].decl.range == base[key].decl.range is not None, key


def test_strings_toml_values_and_keywords_give_the_same_typed_values():
    from_strings = CubeScene.from_settings({"order": "3", "maxh": "1", "mechanics": "no",
                                            "model": "quarter", "outputs": "figures, vtk"})
    from_toml = CubeScene.from_settings(tomllib.loads(
        'order = 3\nmaxh = 1\nmechanics = false\nmodel = "quarter"\noutputs = "vtk,figures"'))
    from_python = CubeScene(order=3, maxh=1.0, mechanics=False, model="quarter",
                            outputs={"vtk", "figures"})
    assert from_strings == from_toml == from_python
    assert isinstance(from_strings.maxh, float) and isinstance(from_toml.maxh, float)
    assert from_strings.outputs == {"vtk", "figures"}


@given(st.tuples(*[st.floats(min_value=1e-3, max_value=100)] * 3))
def test_a_tuple_round_trips_from_string_toml_and_python(axes):
    scene = AtrophyScene.declarations()["semi_axes"]
    text = ",".join(repr(a) for a in axes)
    toml = tomllib.loads(f"semi_axes = [{', '.join(repr(a) for a in axes)}]")["semi_axes"]
    values = [scene.convert(text), scene.convert(toml), scene.convert(axes),
              scene.convert(list(axes)), scene.convert(scene.to_json(axes))]
    assert all(v == tuple(axes) and isinstance(v, tuple) for v in values)


def test_tuples_are_tuples_in_python_lists_in_results_and_strings_still_read():
    scene = AtrophyScene(semi_axes="3,2.5,2", seed="0,0,-1.5", times="7, 4", t_end=10.0,
                         dt=1.0, gray_thickness=0.5, snapshots=1)
    assert scene.semi_axes == (3.0, 2.5, 2.0) and scene.seed == (0.0, 0.0, -1.5)
    assert scene.times == (7.0, 4.0)
    settings = scene.settings()
    assert settings["semi_axes"] == [3.0, 2.5, 2.0] and settings["seed"] == [0.0, 0.0, -1.5]
    assert settings["times"] == [7.0, 4.0] and settings["outputs"] == "vtk,figures"
    assert AtrophyScene.from_settings(settings) == scene
    # results.json of a run before tuples were typed: the parameters were strings
    old = {**settings, "semi_axes": "3,2.5,2", "seed": "0,0,-1.5", "times": "7,4"}
    assert AtrophyScene.from_settings(old) == scene
    assert AtrophyScene(seed="uniform").seed_centre() is None
    assert AtrophyScene.from_settings({"times": ""}).times == ()


def test_a_sweep_file_takes_tuples_as_lists_or_strings(tmp_path):
    path = tmp_path / "brain.toml"
    path.write_text('scene = "atrophy"\n[fixed]\nsemi_axes = [3, 2.5, 2]\n'
                    'gray_thickness = 0.5\n[vary]\nseed = [[0, 0, -1], "0,0,-1", "uniform"]\n')
    cases = load_sweep(path).cases()
    scenes = [case.build() for case in cases]
    assert [s.semi_axes for s in scenes] == [(3.0, 2.5, 2.0)] * 3
    assert [s.seed for s in scenes] == [(0.0, 0.0, -1.0), (0.0, 0.0, -1.0), "uniform"]
    with pytest.raises(ParameterError, match="fixed.nu"):
        parse_sweep({"scene": "atrophy", "fixed": {"nu": [0.3, 0.4]}})
    with pytest.raises(ParameterError, match="vary.seed"):
        parse_sweep({"scene": "atrophy", "vary": {"seed": [[0, 0, "x"]]}})
    swept = parse_sweep({"scene": "atrophy"}).with_settings({"semi_axes": "3,2.5,2"})
    assert swept.fixed == {"semi_axes": [3.0, 2.5, 2.0]}


@pytest.mark.parametrize("declaration, names", [
    (MU, ("cube", "hemisphere", "disc", "cylinder", "skin", "custom")),
    (NU, ("cube", "hemisphere", "disc", "cylinder", "skin", "custom", "atrophy")),
    (K1, ("disc", "custom")), (K2, ("disc", "custom")), (KAPPA, ("disc", "custom")),
])
def test_the_material_block_is_declared_once(declaration, names):
    key = {MU: "mu", NU: "nu", K1: "k1", K2: "k2", KAPPA: "kappa"}[declaration]
    for name in names:
        assert SCENES[name].declarations()[key].decl is declaration, name
    assert {name for name, cls in SCENES.items() if key in cls.declarations()} == set(names)


def test_scenes_keep_their_own_material_defaults():
    """The paper's idealized material (also the skin's, ref. [77]) and the disc's GOH media
    (Holzapfel et al. 2000)."""
    assert (CubeScene().mu, CubeScene().nu) == (0.55, 0.4)
    disc = DiscScene()
    assert (disc.mu, disc.nu, disc.k1, disc.k2, disc.kappa) == (0.003, 0.4, 0.0023632, 0.8393,
                                                                 0.0)
    assert (SkinExpansionScene().mu, SkinExpansionScene().nu) == (0.55, 0.4)
    assert AtrophyScene().nu == 0.49


def test_outputs_are_parsed_in_one_place():
    assert Outputs("figures, vtk") == {"vtk", "figures"} and str(Outputs("figures,vtk")) == \
        "vtk,figures"
    assert Outputs("none") == Outputs("") == Outputs([]) == set() and str(Outputs()) == "none"
    with pytest.raises(ParameterError, match="^outputs = 'pdf' is out of range: allowed a "
                                             "comma list of curvature, figures, growth, vtk"):
        Outputs("pdf")
    assert OUTPUT_NAMES == ("incompatibility", "mechanics", *OUTPUTS)
    assert output.OUTPUTS is OUTPUTS
    assert _outputs("curvature,incompatibility") == {"mechanics": False, "outputs": "curvature"}
    # what output.write reads from results.json: the recorded string, old or new
    for recorded, expected in (("vtk,figures", {"vtk", "figures"}), ("none", set()),
                               ("growth", {"growth"})):
        results = Results(scene="cube", params={"outputs": recorded}, units={}, mesh=None)
        assert output.wanted(results) == expected


def test_metric_units_belong_to_the_scene_that_reports_them():
    assert dict(Scene.metrics) == {}
    assert "rotation_rate" not in SkinExpansionScene.metrics
    with pytest.raises(KeyError):
        SkinExpansionScene.metric_unit("rotation_rate")
    assert SCENES["cylinder"].metric_unit("rotation_rate") == "1/mm"
    assert SCENES["folding"].metric_unit("onset_wavelength") == "cm"


@pytest.mark.parametrize("text, inside, outside", [
    ("> 0", [1e-9, 5.0], [0.0, -1.0]), (">= 1", [1.0, 2.0], [0.999]),
    ("< 0.5", [0.49, -3.0], [0.5]), ("<= 1", [1.0], [1.01]),
    ("(-1, 0.5)", [-0.99, 0.0, 0.49], [-1.0, 0.5]), ("[0, 1/3]", [0.0, 1 / 3], [0.34, -1e-9]),
    ("(0, 1]", [1.0, 0.5], [0.0, 1.1]),
])
def test_ranges(text, inside, outside):
    rng = Range(text)
    assert all(x in rng for x in inside) and not any(x in rng for x in outside)


def test_a_malformed_declaration_fails_where_it_is_written():
    with pytest.raises(ValueError, match="range"):
        Param("x", range="positive")
    with pytest.raises(ValueError, match="range"):
        param(1.0, "x", range="=> 0")


def test_a_tuple_of_any_length():
    kind = _Floats(None, "> 0")
    assert kind.parse("") == () and kind.parse("1, 2.5") == (1.0, 2.5)
    assert kind.valid((1.0, 2.0, 3.0, 4.0)) and not kind.valid((1.0, 0.0))
    assert kind.allowed() == "a comma list of numbers in (0, 1e+12]"
    assert not kind.valid((1.0, 1e308))
