"""Hostile input that passes the types must not crash, hang or eat memory: every numeric
parameter of every scene through the command line, the element estimate before meshing, and
expression limits."""

import json
import math

import ngsolve as ngs
import pytest

from geometries import bilayer, cube, cylinder, disc, estimate, hemisphere, skin_patch
from ngincompat.cli import main
from ngincompat.errors import ExpressionError, ParameterError
from ngincompat.mechanics.expressions import MAX_DEPTH, MAX_LENGTH, parse_expression
from ngincompat.parameters import _Bool, _Choice, _Floats, _Int, _Outputs, _WordsOrFloats
from ngincompat.scenes import SCENES
from ngincompat.studies.corpus import HOSTILE, HOSTILE_INT, numeric_parameters

# ----------------------------------------------------------------- the generated corpus


def _numeric(cls):
    return [(key, cls.declarations()[key]) for key in numeric_parameters(cls)]


def _numbers(p):
    """The kind of one number of the parameter (of each component of a tuple)."""
    kind = p.kind.floats if isinstance(p.kind, _WordsOrFloats) else p.kind
    return kind.item if isinstance(kind, _Floats) else kind


def _texts(p, value):
    """``value`` as --set text for the parameter: a tuple gets it in every component."""
    kind = p.kind.floats if isinstance(p.kind, _WordsOrFloats) else p.kind
    if isinstance(kind, _Floats) and value:
        return ",".join([value] * (kind.length or 1))
    return value


CORPUS = [(name, key) for name, cls in SCENES.items() for key, _ in _numeric(cls)]


def _legitimate(cls, key, text):
    """Whether the value is allowed (its declared range and the scene's checks): then it
    would run, and the corpus skips it."""
    try:
        cls.from_settings({key: text})
    except ParameterError:
        return False
    return True


@pytest.mark.parametrize("scene, key", CORPUS, ids=[f"{s}-{k}" for s, k in CORPUS])
def test_every_numeric_parameter_refuses_hostile_values_in_one_line(scene, key, tmp_path,
                                                                    capsys):
    p = SCENES[scene].declarations()[key]
    values = HOSTILE + (HOSTILE_INT if isinstance(p.kind, _Int) else ())
    refused = _refused(scene, key, [_texts(p, value) for value in values], tmp_path, capsys,
                       also="maxh")
    # 1e308, inf, -inf, nan and a wrong type are refused by every numeric parameter
    assert refused >= 5


def _refused(scene, key, texts, tmp_path, capsys, also=None):
    """Run the scene with each of ``texts`` as ``key`` that it does not allow: exit 2, one
    line naming the parameter (or ``also``), no traceback, no folder left. Returns how many
    were refused."""
    refused = 0
    for text in texts:
        if _legitimate(SCENES[scene], key, text):
            continue
        out = tmp_path / f"out_{refused}"
        code = main(["run", scene, "--set", f"{key}={text}", "--out", str(out), "-q"])
        captured = capsys.readouterr()
        lines = captured.err.strip().splitlines()
        assert code == 2, (text, captured.err)
        assert len(lines) == 1 and (key in lines[0] or (also and also in lines[0])), lines
        assert "Traceback" not in captured.err + captured.out
        assert not out.exists(), text
        refused += 1
    return refused


#: Every parameter of a closed set of values (yes/no, a choice, the outputs), by scene.
WORDS = [(name, key) for name, cls in SCENES.items()
         for key, p in cls.declarations().items()
         if isinstance(p.kind, (_Bool, _Choice, _Outputs))]


@pytest.mark.parametrize("scene, key", WORDS, ids=[f"{s}-{k}" for s, k in WORDS])
def test_every_word_parameter_refuses_empty_wrong_and_numeric_values_in_one_line(
        scene, key, tmp_path, capsys):
    """The corpus of the numbers for the other kinds: empty, an unknown word, a number."""
    assert _refused(scene, key, ("", "no-such-value", "1e308"), tmp_path, capsys) >= 2


@pytest.mark.parametrize("key", ["growth", "direction", "material", "fiber"])
def test_the_custom_scenes_named_choices_refuse_an_unknown_name_naming_the_parameter(
        key, tmp_path, capsys):
    """Registered kinds and directions are open sets of names: an unknown one (``fiber=abc``
    once reported "direction 'abc'") is refused under its own parameter's name."""
    assert _refused("custom", key, ("no-such-value",), tmp_path, capsys) == 1


def test_the_issues_infinite_first_residual_is_refused_as_bad_input_and_writes_nothing(
        tmp_path, capsys):
    """theta = 1 + 1e300 X1 t overflowed the residual at the first step and exited 0, "done"
    with 0 Newton iterations (inf <= inf passed the tolerance). Its volume growth theta^3
    overflows, so it is now refused before anything is built: exit 2 naming theta, no folder.
    The solver's own verdict on an infinite residual is tested in test_solver.py."""
    out = tmp_path / "out"
    code = main(["run", "custom", "--preset", "preview", "--set", "theta=1 + 1e300*X1*t",
                 "--set", "outputs=none", "--out", str(out), "-q"])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err, err
    assert "theta" in err and "overflows" in err
    assert not out.exists()


@pytest.mark.parametrize("scene, key", CORPUS, ids=[f"{s}-{k}" for s, k in CORPUS])
def test_every_number_has_a_physical_range_and_is_refused_past_its_bound(scene, key,
                                                                        tmp_path, capsys):
    """Both bounds declared (``list -v`` shows them; for a float, not the generic limit of
    the type): past the upper bound, and below the lower one, a value is refused in one line
    that names the parameter and its range."""
    cls = SCENES[scene]
    p = cls.declarations()[key]
    bounds = _numbers(p).range
    assert bounds is not None and bounds.bounded, (scene, key, bounds)
    high = bounds.high if bounds.high_open else bounds.high * 2 if bounds.high > 0 else \
        bounds.high + 1
    low = bounds.low if bounds.low_open else bounds.low - max(1.0, abs(bounds.low))
    for value in (high, low):
        number = int(value) if isinstance(p.kind, _Int) else value
        assert main(["run", scene, "--set", f"{key}={_texts(p, repr(number))}",
                     "--out", str(tmp_path / "out"), "-q"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert not (tmp_path / "out").exists()
        assert len(err) == 1 and err[0].startswith(f"ngincompat: error: {key} = "), err
        assert bounds.text in err[0], err
    assert bounds.text in p.allowed()


def test_the_corpus_covers_every_scene_and_the_named_hostile_inputs():
    assert {s for s, _ in CORPUS} == set(SCENES)
    for scene, key in [("hemisphere", "R0"), ("disc", "R0"), ("disc", "height"),
                       ("cylinder", "area"), ("cylinder", "length"), ("folding", "height"),
                       ("folding", "length"), ("folding", "cortex_thickness"), ("cube", "side"),
                       ("cube", "mu"), ("atrophy", "t_end"), ("folding", "axon_rate"),
                       ("skin", "growth_order"), ("folding", "growth_order"), ("skin", "K"),
                       ("skin", "volume"), ("folding", "cortex_rate"), ("atrophy", "seed")]:
        assert (scene, key) in CORPUS
        for value in ("inf", "1e308"):
            assert not _legitimate(SCENES[scene], key, value), (scene, key, value)


@pytest.mark.parametrize("settings, name", [
    ({"t_end": "1e12"}, "t_end"),                 # atrophy: longer than a lifetime
    ({"t_end": "100", "dt": "0.001"}, "dt"),      # 1e5 steps
    ({"growth_order": "100000000000000000000"}, "growth_order"),
])
def test_durations_and_counts_that_would_never_end_are_refused(settings, name):
    scene = "atrophy" if "t_end" in settings else "skin"
    with pytest.raises(ParameterError, match=f"^{name} = "):
        SCENES[scene].from_settings(settings)
    with pytest.raises(ParameterError, match="^dt = .*time steps"):
        SCENES["skin"].from_settings({"hold_days": "365", "dt": "0.01"})
    with pytest.raises(ParameterError, match="^dt = .*time steps"):
        SCENES["folding"].from_settings({"t_end": "1000", "dt": "0.05"})


# ----------------------------------------------------------------- the element estimate

MESHES = [
    ("cube tet", lambda: cube(maxh=0.1, elements="tet"),
     lambda: estimate.cube_elements(maxh=0.1, elements="tet")),
    ("cube hex", lambda: cube(maxh=0.2), lambda: estimate.cube_elements(maxh=0.2)),
    ("hemisphere", lambda: hemisphere(maxh=0.3, curve_order=1, centre_maxh=0.01),
     lambda: estimate.hemisphere_elements(maxh=0.3, centre_maxh=0.01)),
    ("disc", lambda: disc(maxh=0.15, curve_order=1), lambda: estimate.disc_elements(maxh=0.15)),
    ("cylinder", lambda: cylinder(maxh=0.15, curve_order=1),
     lambda: estimate.cylinder_elements(maxh=0.15)),
    ("thin cylinder", lambda: cylinder(area=1e-3, maxh=0.25, curve_order=1),
     lambda: estimate.cylinder_elements(area=1e-3, maxh=0.25)),
    ("skin", lambda: skin_patch(maxh=1.0, curve_order=1),
     lambda: estimate.skin_patch_elements(maxh=1.0)),
    ("bilayer", lambda: bilayer(maxh=0.3, cortex_maxh=0.05),
     lambda: estimate.bilayer_elements(maxh=0.3, cortex_maxh=0.05)),
    ("bilayer refined top", lambda: bilayer(length=1.0, height=0.6, cortex=0.1, maxh=0.3,
                                            cortex_maxh=0.05, top_maxh=0.0125),
     lambda: estimate.bilayer_elements(length=1.0, height=0.6, cortex=0.1, maxh=0.3,
                                       cortex_maxh=0.05, top_maxh=0.0125)),
]

#: The estimate only has to tell a mesh that fits from one that does not.
FACTOR = 4


@pytest.mark.parametrize("label, build, guess", MESHES, ids=[m[0] for m in MESHES])
def test_the_element_estimate_is_within_a_factor_4_of_the_mesh(label, build, guess):
    ne, estimated = build().ne, guess()
    assert ne / FACTOR <= estimated <= FACTOR * ne, (label, ne, estimated)


def test_every_scene_meshed_from_a_geometry_has_an_estimate():
    for name, cls in SCENES.items():
        elements, _ = cls().mesh_estimate()
        assert 1 <= elements <= cls().max_elements, name


def test_maxh_0001_on_the_cube_is_refused_before_meshing_naming_maxh_and_the_limit(
        tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", "cube", "--maxh", "0.001", "--set", "elements=hex", "--out", str(out),
                 "-q"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("ngincompat: error: maxh = 0.001 ")
    assert "1e+09 elements" in err and "max_elements = 1000000" in err
    assert "--set max_elements=N" in err
    assert not out.exists()


def test_the_limit_can_be_raised_and_counts_unknowns_by_order():
    with pytest.raises(ParameterError, match="^maxh = "):
        SCENES["cube"].from_settings({"maxh": "0.01", "elements": "hex"})  # 1e6 hexahedra
    SCENES["cube"].from_settings({"maxh": "0.01", "max_elements": "2000000", "elements": "hex",
                                  "max_dofs": "1000000000", "order": "1"})
    with pytest.raises(ParameterError, match="unknowns at order 10"):
        SCENES["cube"].from_settings({"maxh": "0.02", "order": "10", "elements": "hex"})


def test_a_huge_body_is_refused_by_its_element_count():
    with pytest.raises(ParameterError, match="^maxh = .*hemisphere mesh would have about"):
        SCENES["hemisphere"].from_settings({"R0": "1000", "centre_maxh": "0.05"})
    assert math.isinf(estimate.disc_elements(R0=1e308, height=1e308, maxh=1e-308))


def test_a_body_within_the_element_count_but_past_the_memory_is_refused_by_its_unknowns():
    """A disc 1000 mm high at the preview's mesh (about 250,000 elements, under max_elements)
    ran past ten minutes of the corpus's limit: its ~1e6 unknowns are past the default
    max_dofs, which a direct factorization of a 3-D problem holds in a workstation's memory;
    raised, it passes."""
    with pytest.raises(ParameterError, match="disc mesh would have about 9.8e\\+05 unknowns.*"
                                             "max_dofs = 500000"):
        SCENES["disc"].from_settings({"height": "1000"}, preset="preview")
    SCENES["disc"].from_settings({"height": "1000", "max_dofs": "2000000"}, preset="preview")


# ----------------------------------------------------------------- expressions

@pytest.mark.parametrize("text, what", [
    ("-" * 10_000 + "1", "characters"),
    ("-" * (MAX_LENGTH - 1) + "1", "nested"),
    ("+".join(["X1"] * 3000), "characters"),
    ("+".join(["X1"] * (MAX_DEPTH + 5)), "nested"),
    ("1+" * 500_000 + "1", "characters"),
    ("(" * 900 + "1" + ")" * 900, "not a valid expression"),
    ("min(" * 120 + "X1" + ",X2)" * 120, "nested"),
])
def test_expression_limits_refuse_in_one_short_line_naming_the_parameter(text, what):
    with pytest.raises(ExpressionError) as info:
        parse_expression(text, name="theta")
    message = str(info.value)
    assert message.startswith("theta = ") and what in message
    assert "\n" not in message and len(message) < 250


def test_an_unknown_name_in_a_long_expression_quotes_at_most_80_characters():
    text = "1 + " + "X1*" * 300 + "foo"
    with pytest.raises(ExpressionError) as info:
        parse_expression(text, name="theta")
    quoted = str(info.value).split(" = ", 1)[1].split("'")[1]
    assert len(quoted) <= 80


def test_a_hostile_theta_is_refused_by_the_custom_scene_through_the_command_line(
        tmp_path, capsys):
    out = tmp_path / "out"
    code = main(["run", "custom", "--set", "theta=" + "-" * 10_000 + "1", "--out", str(out),
                 "-q"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and len(err) < 300
    assert not out.exists()


@pytest.mark.parametrize("mechanics", ["false", "true"])
def test_a_metric_that_overflows_fails_the_run_and_no_file_of_its_state_is_written(
        tmp_path, capsys, mechanics):
    """theta = 1 + sin(1e300 X1)^2 is finite and in [1, 2], and the mechanics converge on it,
    but its gradient of 1e300 overflows the incompatibility's norms: exit 3 naming those
    metrics, the finite ones kept, and on disk results.json alone (no fields, figures or
    growth data of a state whose metrics are not finite)."""
    out = tmp_path / "out"
    code = main(["run", "custom", "--preset", "preview", "--set", "theta=1 + sin(1e300*X1)**2",
                 "--set", f"mechanics={mechanics}", "--set", "outputs=vtk,figures,growth",
                 "--out", str(out), "-q"])
    err = capsys.readouterr().err
    assert code == 3, err
    assert "Traceback" not in err and "G_norm_L2" in err.strip().splitlines()[-1]
    written = json.loads((out / "results.json").read_text())
    assert written["status"] == "not converged"
    assert "metrics not finite: burgers_max, G_error_L2_rel, G_norm_L2" in written["error"]
    assert written["metrics"]["G_norm_L2"] is None
    assert sorted(p.name for p in out.iterdir()) == ["results.json"]
    assert written["files"] == ["results.json"]
    if mechanics == "true":         # the solve converged: its finite metrics are kept
        assert written["solver"]["growth"]["converged"]
        assert 0 < written["metrics"]["strain_energy"] < math.inf


# ----------------------------------------------------------------- the mixed formulation

@pytest.mark.parametrize("scene, settings", [("atrophy", ["nu=0"]), ("atrophy", ["nu=1e-300"]),
                                             ("cube", ["formulation=mixed", "nu=0"]),
                                             ("cube", ["formulation=mixed", "nu=1e-7"]),
                                             ("cube", ["formulation=mixed", "nu=-0.5"])])
def test_the_mixed_formulation_refuses_nu_below_its_floor_before_computing(scene, settings,
                                                                         tmp_path, capsys):
    """Its pressure term p^2 / (2 lambda) needs lambda / mu >= 2e-6: atrophy at nu = 0 and at
    nu = 1e-300 (the out-of-process corpus; a non-finite energy) ended "not converged" at
    t = 0, exit 3 for a bad input."""
    out = tmp_path / "out"
    args = [a for s in settings for a in ("--set", s)]
    assert main(["run", scene, *args, "--out", str(out), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("ngincompat: error: nu = "), err
    assert "mixed formulation" in err[0] and not out.exists()
    SCENES["cube"].from_settings({"nu": "0"})       # the displacement formulation takes it


# ------------------------------------------- what an attack of tiny values and odd input found

@pytest.mark.parametrize("scene, setting", [
    ("cube", "side=1e-10"), ("disc", "height=1e-300"), ("cylinder", "area=1e-320"),
    ("folding", "length=1e-320"), ("hemisphere", "centre_maxh=1e-300"), ("disc", "k2=1e-320"),
    ("atrophy", "seed_radius=1e-320"), ("folding", "t_end=1e-320"),
    ("folding", "cortex_thickness=1e-320"), ("folding", "mu_white=1e-320"),
    ("folding", "cortex_rate=1e-320"), ("disc", "k1=1e-320")])
def test_tiny_positive_values_are_refused_before_meshing_in_one_line(scene, setting, tmp_path,
                                                                     capsys):
    """Each passed its "(0, x]" range and ended in a traceback (OCC, Netgen, a division by
    zero, a singular matrix) or ran for minutes: now refused by the parameter's physical
    floor, or as a subnormal number, naming it."""
    key = setting.split("=")[0]
    out = tmp_path / "out"
    assert main(["run", scene, "--set", setting, "--out", str(out), "-q"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"ngincompat: error: {key} = "), lines
    assert "Traceback" not in captured.err and not out.exists()


@pytest.mark.parametrize("scene, setting", [("disc", "height=0.001"),
                                            ("cylinder", "length=0.001")])
def test_a_body_too_thin_to_mesh_is_bad_input_naming_its_lengths(scene, setting, tmp_path,
                                                                 capsys):
    """A disc 1e-3 high or a cylinder 1e-3 long at the preview's mesh size passes every range
    and stopped Netgen's mesher with a traceback (exit 1): now exit 2, the last line of the
    error naming the scene's lengths and what to change, and no folder left behind."""
    key, value = setting.split("=")
    out = tmp_path / "out"
    assert main(["run", scene, "--preset", "preview", "--set", setting, "--out", str(out),
                 "-q"]) == 2
    captured = capsys.readouterr()
    last = captured.err.strip().splitlines()[-1]
    assert last.startswith(f"ngincompat: error: the mesher failed on this {scene} geometry")
    assert f"{key} = {value}" in last and "maxh = " in last and "thinnest dimension" in last
    assert "Traceback" not in captured.err and not out.exists()


def test_a_stress_free_atrophy_has_a_zero_relative_residual():
    """A seed the mesh does not see (seed_radius at its floor, 10 um, in a 1 cm mesh)
    atrophies nothing: stresses and residual are 0, and their ratio was a ZeroDivisionError."""
    from ngincompat.scenes.atrophy.case import relative

    assert relative(0.0, 0.0) == 0.0 and relative(2.0, 4.0) == 0.5
    assert relative(1e-3, 0.0) == math.inf


def test_the_discs_checks_are_left_out_of_a_state_that_never_grew():
    """A disc whose first growth step fails (k1 = 1e6 in the preview) is measured at t = 0,
    where b of eq. (22) is zero: the checks relative to it were a ZeroDivisionError."""
    case = SCENES["disc"](maxh=0.5, order=1).build()
    assert case.verify(None, {"b_e3": ngs.CF((0.0, 0.0, 0.0))}) == {}


def test_the_hemispheres_checks_are_left_out_of_a_state_that_never_grew():
    """nu = -0.9999999999999999 (inside (-1, 0.5), found by the corpus): the first growth
    step fails and the state at t = 0, where b vanishes, is measured; the alignment of b
    relative to its largest value was a ZeroDivisionError (a traceback instead of exit 3)."""
    case = SCENES["hemisphere"](maxh=0.5, order=1).build()
    zero = ngs.CF((0.0, 0.0, 0.0))
    assert case.verify(object(), {"b_radial": zero, "b_meridional": zero,
                                  "b_circumferential": zero}) == {}


@pytest.mark.parametrize("value", ["0", "abc", "-1", "100000", "1.5", "\uff13", "", " "])
def test_an_unusable_ngs_num_threads_is_refused_in_one_line(value, monkeypatch, capsys,
                                                            tmp_path):
    """NGSolve reads NGS_NUM_THREADS when it is imported: 0 computed garbage, and so did an
    empty value (NGSolve's 0; found by the corpus), a word raised a traceback, -1 and 100000
    broke NGSolve's import. Checked before anything is imported."""
    monkeypatch.setenv("NGS_NUM_THREADS", value)
    assert main(["run", "cube", "--out", str(tmp_path / "out"), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("ngincompat: error: NGS_NUM_THREADS = "), err
    assert "[1, 256]" in err[0] and not (tmp_path / "out").exists()


@pytest.mark.parametrize("text, what", [("0x10", "'0x10'"), ("1_0", "'1_0'"),
                                        ("1 + 0o7 * t", "'0o7'"), ("\uff54", "character")])
def test_theta_takes_decimal_numbers_and_ascii_only(text, what):
    """Python's parser reads 0x10, 1_0 and a full-width t (as t): none is how a growth law is
    written, and the message should not pretend they are."""
    with pytest.raises(ExpressionError, match=what):
        parse_expression(text, name="theta")
    parse_expression("1 + 0.5*t + .25*X1 + 2e-1*X2 + 1E+0*X3 + 3.", name="theta")   # taken


@pytest.mark.parametrize("settings, key", [
    (["--set", "theta=1e-320"], "theta"), (["--set", "theta=1e-10"], "theta"),
    (["--set", "theta=1 - 0.9999*X1"], "theta")], ids=["subnormal", "tiny", "near-zero-edge"])
def test_a_degenerate_growth_is_bad_input_not_a_solve_that_fails(settings, key, tmp_path,
                                                                capsys):
    """theta = 1e-320 was reported "not converged" (exit 3): it is no growth a tissue can
    have, refused (exit 2) below the floor of the growth indicator, naming it and where."""
    out = tmp_path / "out"
    code = main(["run", "custom", *settings, "--set", "maxh=1", "--set", "order=1",
                 "--out", str(out), "-q"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith(f"ngincompat: error: {key} = ") and "0.001" in err[0], err


@pytest.mark.parametrize("settings, message", [
    (["nu=-0.995"], "nu = -0.995 is out of range: allowed in [-0.99, 0.5)"),
    (["nu=0.499999"], "nu = 0.499999 is out of range: allowed <= 0.49999 for the displacement "
                      "formulation, which locks nearer incompressibility: use formulation=mixed")])
def test_poissons_ratio_is_refused_where_the_formulation_fails(settings, message, tmp_path,
                                                               capsys):
    """The cube at nu = -0.999 and at 0.499999 (displacement formulation) ended "not
    converged" part way (the corpus); at 0.499999 the mixed formulation converges."""
    out = tmp_path / "out"
    args = [a for s in settings for a in ("--set", s)]
    assert main(["run", "cube", "--preset", "preview", *args, "--out", str(out), "-q"]) == 2
    assert capsys.readouterr().err.strip() == f"ngincompat: error: {message}"
    assert not out.exists()
    SCENES["cube"].from_settings({"nu": "0.499999", "formulation": "mixed"})
